"""Auto-scale: no hole at the chosen field and holes 1% beyond it; cover shows the whole source."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.errors import FitError
from lenslab.fit.autoscale import autoscale, scaled_lens
from lenslab.lenses import Camera
from lenslab.warp import exact_map


def centres(w: int, h: int) -> np.ndarray:
    gx, gy = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return np.stack([gx, gy], axis=-1)


def holes(src: Camera, dst: Camera) -> int:
    """Output pixels whose ray exists but which the warp cannot fill (its own map, pixel centres)."""
    pts = centres(*dst.size)
    _, ray = dst.lens.pixel_to_dir(pts)
    _, valid = exact_map(src, dst, pts)
    return int((ray & ~valid).sum())


def cropped(src: Camera, dst: Camera) -> int:
    """Source pixels the output does not show."""
    _, d, ok = src.pixel_to_world(centres(*src.size))
    _, seen = dst.world_to_pixel(d)
    return int((ok & ~seen).sum())


CASES = [
    # (source, its size, output, its size, output yaw)
    ("barrel:k1=-0.25,fov=90", (320, 240), "perspective:fov=90", (320, 240), 0.0),
    ("pincushion:k1=0.2,fov=70", (320, 240), "perspective:fov=70", (300, 200), 0.0),
    ("equirect:lon_min=-60,lon_max=60,lat_min=-40,lat_max=40", (300, 200), "perspective:fov=90", (320, 240), 10.0),
    ("fisheye:fov=160,mapping=equisolid", (256, 256), "perspective:fov=100", (256, 192), 0.0),
    ("perspective:fov=100", (320, 240), "equirect:lon_min=-30,lon_max=30,lat_min=-20,lat_max=20", (240, 160), 0.0),
]


@pytest.mark.parametrize("src_spec,src_size,dst_spec,dst_size,yaw", CASES, ids=[c[0] for c in CASES])
def test_fill_leaves_no_hole_and_one_percent_wider_does(src_spec, src_size, dst_spec, dst_size, yaw):
    src = Camera.from_spec(src_spec, src_size)
    dst = Camera.from_spec(dst_spec, dst_size, yaw=yaw)
    res = autoscale(src, dst, "fill")
    assert holes(src, res.camera) == 0
    wider = Camera(scaled_lens(res.lens, 1.01), dst.pose)
    assert holes(src, wider) > 0
    assert res.bad_at_scale == 0 and res.bad_one_percent_beyond == holes(src, wider)
    assert res.cobyla.startswith("agrees")


@pytest.mark.parametrize("src_spec,src_size,dst_spec,dst_size,yaw", CASES[:4], ids=[c[0] for c in CASES[:4]])
def test_cover_shows_all_the_source_and_one_percent_narrower_does_not(src_spec, src_size, dst_spec, dst_size, yaw):
    src = Camera.from_spec(src_spec, src_size)
    dst = Camera.from_spec(dst_spec, dst_size, yaw=yaw)
    res = autoscale(src, dst, "cover")
    assert cropped(src, res.camera) == 0
    narrower = Camera(scaled_lens(res.lens, 1 / 1.01), dst.pose)
    assert cropped(src, narrower) > 0
    fill = autoscale(src, dst, "fill")
    assert fill.scale < res.scale  # filling the frame always crops some of a distorted source


def test_barrel_correction_numbers():
    """Barrel distortion squeezes the periphery in, so the lens sees more than a perspective of its
    nominal fov. Filling a 4:3 frame is limited by the middle of the top and bottom edges: the source's
    edge v_d = 0.75 sees r_u = 0.75 / (1 - 0.25 * 0.75^2), and the output's top row of pixel centres
    (v = 0.75 (1 - 1/480)) must not look beyond it."""
    src = Camera.from_spec("barrel:k1=-0.25,fov=90", (640, 480))
    dst = Camera.from_spec("perspective:fov=90", (640, 480))
    fill = autoscale(src, dst, "fill")
    r_u = 0.75 / (1 - 0.25 * 0.75 ** 2)
    expected = 2 * np.degrees(np.arctan(r_u / (0.75 * (1 - 1 / 480))))  # 98.78 deg
    # the binding pixels are the two central columns, half a pixel either side of the axis: 1e-3 deg
    assert fill.lens.fov == pytest.approx(expected, abs=1e-3)
    assert holes(src, Camera(scaled_lens(fill.lens, 1.001), dst.pose)) > 0  # the bracket is that tight too


def test_more_samples_can_only_narrow_the_fill():
    src = Camera.from_spec("barrel:k1=-0.25,fov=90", (160, 120))
    dst = Camera.from_spec("perspective:fov=90", (160, 120))
    one = autoscale(src, dst, "fill", samples=1)
    four = autoscale(src, dst, "fill", samples=4)
    assert four.scale <= one.scale


def test_a_full_panorama_leaves_nothing_to_fill_and_the_field_is_kept():
    # A full panorama fills every field up to the model's limit (a 360-degree fisheye is a flat disc of
    # one direction at its rim): there is no answer to search for, the field the user gave stays.
    src = Camera.from_spec("equirect", (360, 180))
    for spec, fov in (("fisheye:fov=90", 90.0), ("fisheye:fov=240,mapping=stereographic", 240.0),
                      ("perspective:fov=90", 90.0)):
        res = autoscale(src, Camera.from_spec(spec, (128, 128), pitch=-90.0), "fill")
        assert res.kept and res.lens.fov == fov, spec
        assert "nothing to fill" in res.report()[0] and "kept" in res.report()[0]


def test_what_cannot_be_done_is_an_error_that_says_so():
    pano = Camera.from_spec("equirect", (360, 180))
    with pytest.raises(FitError, match="shows all of the source"):
        autoscale(pano, Camera.from_spec("perspective:fov=90", (64, 64)), "cover")
    with pytest.raises(FitError, match="no field of view to scale"):
        autoscale(pano, Camera.from_spec("cubemap", (96, 64)), "fill")
    with pytest.raises(FitError, match="mode"):
        autoscale(pano, Camera.from_spec("perspective", (64, 64)), "crop")
    # looking away from a partial panorama: even the narrowest view has a hole
    part = Camera.from_spec("equirect:lon_min=-30,lon_max=30,lat_min=-20,lat_max=20", (120, 80))
    with pytest.raises(FitError, match="free of holes"):
        autoscale(part, Camera.from_spec("perspective", (64, 64), yaw=90), "fill")


def test_autoscale_is_deterministic():
    src = Camera.from_spec("pincushion:k1=0.2,fov=70", (160, 120))
    dst = Camera.from_spec("perspective:fov=70", (160, 120))
    a, b = autoscale(src, dst, "fill"), autoscale(src, dst, "fill")
    assert a.scale == b.scale and a.lens.spec() == b.lens.spec()
