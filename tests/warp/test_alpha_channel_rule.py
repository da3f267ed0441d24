"""One rule of which channel is alpha on every warp path: ``alpha_channel=False`` (data channels such as
``u, v`` or ``R, G, B, Z``; what an EXR's names say) keeps the last channel data through vignetting, its
removal, tiled views, multi-view rigs and the Python ``warp()``; an image that carries alpha keeps it out of
the vignetting. Expected values: lensfun's pa falloff ``1 + k1 r^2`` (r = 1 at the corner) in float64 here,
on constant fields (a constant reads as itself through any filter)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from lenslab.lenses import Camera, Pose, make_lens
from lenslab.warp import tile_cameras, warp, warp_tiles

K1 = -0.3
VIGNETTED = f"optics:vignetting=pa/{K1}/0/0,base=perspective,fov=60"


def pa_falloff(w: int, h: int) -> np.ndarray:
    """``1 + k1 r^2`` at the pixel centres of a w x h image, r the distance from the centre over half the
    diagonal (lensfun's pa model as the optics lens states it)."""
    y, x = np.mgrid[0:h, 0:w] + 0.5
    r = np.hypot(x - w / 2.0, y - h / 2.0) / (0.5 * np.hypot(w, h))
    return 1.0 + K1 * r * r


def constant(h: int, w: int, values) -> np.ndarray:
    return np.broadcast_to(np.asarray(values, np.float32), (h, w, len(values))).copy()


PANO = Camera.from_spec("equirect", (128, 64))


@pytest.mark.parametrize("values", [(0.25, 7.0), (1.0, 2.0, 3.0, 9.0)])
def test_destination_vignetting_dims_every_data_channel(values):
    dst = Camera.from_spec(VIGNETTED, (40, 30))
    out, cover = warp(constant(64, 128, values), PANO, dst, alpha_channel=False)
    assert cover.min() == 1.0
    f = pa_falloff(40, 30)
    for c, v in enumerate(values):  # the last channel too, and a value above 1 is not clipped as alpha
        np.testing.assert_allclose(out[..., c], v * f, rtol=1e-6)  # float32 product of float32 values


def test_an_image_that_carries_alpha_keeps_it_out_of_the_vignetting():
    dst = Camera.from_spec(VIGNETTED, (40, 30))
    out, _ = warp(constant(64, 128, (0.5, 0.5, 0.5, 1.0)), PANO, dst, alpha_channel=True)
    np.testing.assert_allclose(out[..., 0], 0.5 * pa_falloff(40, 30), rtol=1e-6)
    assert np.all(out[..., 3] == 1.0)


def test_source_vignetting_is_removed_from_every_data_channel():
    src = Camera.from_spec(VIGNETTED, (40, 30))
    dst = Camera.from_spec("perspective:fov=60", (40, 30))  # the same rays: samples at the pixel centres
    values = (1.0, 2.0, 3.0, 9.0)
    out, cover = warp(constant(30, 40, values), src, dst, alpha_channel=False)
    f = pa_falloff(40, 30)
    inner = cover == 1.0
    assert inner[2:-2, 2:-2].all()
    for c, v in enumerate(values):
        # read at the pixel centres up to the float32 map's 1e-4 px: 1/f changes < 1e-5 relative over it
        np.testing.assert_allclose(out[..., c][inner], (v / f)[inner], rtol=1e-4)


def test_tiled_views_from_one_panorama_keep_data_channels():
    tiles = [{"lens": VIGNETTED, "yaw": 90.0 * k} for k in range(2)]
    dst = Camera(make_lens("tiled:2x1", (64, 32), tiles=tiles))
    out, cover = warp(constant(64, 128, (0.5, 4.0)), PANO, dst, alpha_channel=False)
    assert cover.min() == 1.0
    f = np.concatenate([pa_falloff(32, 32)] * 2, axis=1)  # each tile dimmed about its own centre
    np.testing.assert_allclose(out[..., 0], 0.5 * f, rtol=1e-6)
    np.testing.assert_allclose(out[..., 1], 4.0 * f, rtol=1e-6)


def test_a_multi_view_rig_keeps_data_channels():
    views = [{"lens": "perspective:fov=90", "yaw": 90.0 * k, "eye": [0.1 * k, 0, 0]} for k in range(2)]
    rig = Camera(make_lens("tiled:2x1", (64, 32), tiles=views))
    sources = [Camera(PANO.lens, Pose(np.eye(3), cam.pose.eye)) for _, _, cam in tile_cameras(rig)]
    panos = [constant(64, 128, (0.5, 3.0))] * 2
    out, cover = warp_tiles(panos, sources, rig, alpha_channel=False)
    assert cover.min() == 1.0
    assert np.all(out[..., 1] == 3.0) and np.all(out[..., 0] == 0.5)  # not clipped to 1 and divided by 3
    out, _ = warp_tiles(panos, sources, rig)  # no names: 2 channels are grey and alpha (alpha_last)
    np.testing.assert_allclose(out[..., 0], 0.5 / 3.0, rtol=1e-6)
    assert np.all(out[..., 1] == 1.0)


def test_the_warp_command_reads_the_exr_names(tmp_path):
    import OpenEXR

    src = tmp_path / "uv.exr"
    u, v = np.full((64, 128), 0.25, np.float32), np.full((64, 128), 6.0, np.float32)
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION}, {"u": u, "v": v}).write(str(src))
    out = tmp_path / "out.exr"
    run = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(src), "--from", "equirect", "--to", VIGNETTED,
                          "--size", "40x30", "--pixel-type", "float", "-o", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    chans = OpenEXR.File(str(out), separate_channels=True).parts[0].channels
    assert {"u", "v"} <= set(chans)
    f = pa_falloff(40, 30)
    np.testing.assert_allclose(chans["u"].pixels, 0.25 * f, rtol=1e-6)
    np.testing.assert_allclose(chans["v"].pixels, 6.0 * f, rtol=1e-6)
