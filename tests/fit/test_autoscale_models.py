"""--autoscale for every lens model, from a full panorama and from a 180-degree fisheye.

The model list is the lens registry's. What is asserted is measured by the warp engine, not by the
auto-scale's own criterion: ``fill`` leaves no empty pixel (an image of ones warped into the answer has
coverage at every pixel whose ray exists), ``cover`` shows every source pixel (an image of ones warped
from the answer back into the source covers every source pixel whose ray exists), and the answer is a
spec that parses, inside its model's range. Models whose parameters hold no field of view are reported
and kept as given.
"""

from __future__ import annotations


import numpy as np
import pytest

from lenslab.errors import FitError, LensError
from lenslab.fit.autoscale import autoscale, autoscale_camera, has_field
from lenslab.lenses import REGISTRY, Camera, make_lens
from lenslab.warp import warp

SIZE = (32, 32)  # output; small: every model runs four searches
SOURCES = {
    "full panorama": ("equirect", (96, 48)),
    "180-degree fisheye": ("fisheye:fov=180,mapping=equisolid", (48, 48)),
}
# What auto-scale says when no usable field of the model does the job (tested for its wording below):
# a cover that would need the very end of the model's range, or no field at all.
CANNOT = ("no usable field of view", "no field of view of the")


def _default_lens(model: str):
    try:
        return make_lens(model, SIZE)
    except LensError:
        return None  # a model that needs a named profile (lensfun): nothing to scale without one


MODELS = sorted(REGISTRY)
SCALABLE = [m for m in MODELS if _default_lens(m) is not None and has_field(_default_lens(m))]
FIXED = [m for m in MODELS if _default_lens(m) is not None and not has_field(_default_lens(m))]


def _centres(w: int, h: int) -> np.ndarray:
    gx, gy = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return np.stack([gx, gy], axis=-1)


def _empty_pixels(src: Camera, dst: Camera) -> int:
    """Output pixels whose ray exists but that a warp of an all-ones source leaves with no coverage."""
    w, h = src.size
    _, alpha = warp(np.ones((h, w, 1), np.float32), src, dst, filter="nearest")
    _, ray = dst.lens.pixel_to_dir(_centres(*dst.size))
    return int((ray & (alpha <= 0)).sum())


def _in_range(lens) -> bool:
    """Every numeric parameter of ``lens`` inside its Param's declared range."""
    for p in lens.params:
        v = getattr(lens, p.name)
        if not isinstance(v, float):
            continue
        if p.lo is not None and (v < p.lo or (p.lo_open and v == p.lo)):
            return False
        if p.hi is not None and (v > p.hi or (p.hi_open and v == p.hi)):
            return False
    return True


@pytest.mark.slow
@pytest.mark.parametrize("source", sorted(SOURCES))
@pytest.mark.parametrize("model", SCALABLE)
def test_fill_and_cover_for_every_model(model, source):
    spec, size = SOURCES[source]
    src = Camera.from_spec(spec, size)
    dst = Camera(_default_lens(model))
    for mode in ("fill", "cover"):
        try:
            res = autoscale(src, dst, mode)
        except FitError as exc:
            # Impossible, with a reason a user can act on: a cover that no usable field gives, or a fill
            # from the half-sphere fisheye into a model that always looks behind it too (dual fisheye).
            # A full panorama can always be filled.
            reason = "shows all of the source" if mode == "cover" else "is free of holes"
            assert str(exc).startswith(CANNOT) and reason in str(exc), (model, source, mode, str(exc))
            assert not (mode == "fill" and source == "full panorama"), (model, str(exc))
            continue
        lens = res.lens
        parsed = make_lens(lens.spec(), SIZE)  # the reported spec parses ...
        assert parsed.spec() == lens.spec() and _in_range(parsed), (model, mode, lens.spec())  # ... in range
        cam = Camera(parsed, dst.pose)
        if mode == "fill":
            assert _empty_pixels(src, cam) == 0, (model, source, lens.spec())
        else:
            assert _empty_pixels(cam, src) == 0, (model, source, lens.spec())  # every source pixel is seen
        if source == "full panorama" and mode == "fill":
            # nothing to fill: the field is kept as the user gave it, and the report says so
            assert res.kept and parsed.spec() == dst.lens.spec()
            assert "nothing to fill" in res.report()[0]


def test_a_full_panorama_cannot_be_covered_by_a_perspective_view():
    # A perspective view shows less than a hemisphere: no field of it holds every direction.
    src = Camera.from_spec("equirect", (96, 48))
    with pytest.raises(FitError, match="shows all of the source"):
        autoscale(src, Camera.from_spec("perspective:fov=90", SIZE), "cover")


def test_covering_a_180_degree_fisheye_needs_a_fisheye_of_180_degrees():
    # Analytic: the source's rim is 90 degrees off its axis, so a fisheye shows all of it from fov = 180
    # on and not below; a perspective view would need 180 degrees, the end of its range, and is refused.
    src = Camera.from_spec("fisheye:fov=180,mapping=equisolid", (48, 48))
    res = autoscale(src, Camera.from_spec("fisheye:fov=90", SIZE), "cover")
    # the rim is found by bisection to 2**-40 px, and the scale bracket is 1e-7 wide: 1e-4 degrees covers both
    assert res.lens.fov == pytest.approx(180.0, abs=1e-4)
    with pytest.raises(FitError, match="no field of view of the perspective output shows all"):
        autoscale(src, Camera.from_spec("perspective:fov=90", SIZE), "cover")


@pytest.mark.parametrize("model", FIXED)
def test_models_without_a_field_are_reported_and_kept(model):
    src = Camera.from_spec("equirect", (96, 48))
    dst = Camera(_default_lens(model))
    with pytest.raises(FitError, match=f"cannot auto-scale a {model} output: its parameters hold no field of view"):
        autoscale(src, dst, "fill")
    lines = []
    kept = autoscale_camera(src, dst, "fill", report=lines.append)
    assert kept is dst
    assert lines == [f"cannot auto-scale a {model} output: its parameters hold no field of view to scale; "
                     "its field is kept as given"]


def test_the_registry_is_covered():
    # every model is either scaled, reported as fixed, or needs a profile named in its spec
    needs_profile = [m for m in MODELS if _default_lens(m) is None]
    assert sorted(SCALABLE + FIXED + needs_profile) == MODELS
    assert {"perspective", "fisheye", "equirect"} <= set(SCALABLE)
