"""The conformance suite every registered lens model runs, read from the lens registry.

A new model (one module with its ``examples`` and ``reference_points``) is tested here with no edit:

- its reference points, pinned from outside lenslab (the paper's formula in float64, OpenCV's
  projectPoints, cv2.fisheye, cv2.omnidir, pycolmap, lensfunpy, ffmpeg's v360 definitions) hold both
  ways: ``pixel -> direction`` and ``direction -> pixel``;
- at its extremes (corners, edges, centre, just outside the frame, the six axis directions, the seam,
  the poles, zero, NaN and inf) it returns finite numbers, zero where invalid, and never raises.
(The round trips of every model's examples are in tests/lenses/test_lenses_roundtrip.py, from the same registry.)
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import REGISTRY, make_lens

MODELS = list(REGISTRY)
POINTS = [(name, k) for name in MODELS for k in range(len(REGISTRY.entry(name).capabilities["reference_points"]))]


@pytest.mark.parametrize("name", MODELS)
def test_every_model_has_an_outside_reference(name):
    points = REGISTRY.entry(name).capabilities["reference_points"]
    assert points, f"{name}: give the class reference_points pinned from its paper or library"
    assert all(REGISTRY.canonical(p.spec.partition(":")[0]) == name and p.source for p in points)


@pytest.mark.parametrize("name,k", POINTS, ids=[f"{n}-{k}" for n, k in POINTS])
def test_reference_point_holds_both_ways(name, k):
    p = REGISTRY.entry(name).capabilities["reference_points"][k]
    lens = make_lens(p.spec, p.size)
    xy, ok = lens.dir_to_pixel(np.array([p.direction]))
    assert ok[0], p.source
    assert np.abs(xy[0] - p.pixel).max() <= p.tolerance, (xy[0], p.pixel, p.source)
    d, ok = lens.pixel_to_dir(np.array([p.pixel, np.add(p.pixel, (0.5, 0.0))]))
    assert ok[0], p.source
    # the direction's error, in pixels: its angle over the angle of one pixel step there
    per_px = 2.0 * angle(d[0], d[1])
    error = angle(d[0], np.asarray(p.direction))
    assert error <= p.tolerance * per_px + 1e-15, (d[0], p.direction, p.source)


def angle(a, b) -> float:
    """The angle between two directions, exact near 0 (no arccos of a dot product near 1)."""
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b))


def extreme_pixels(w: int, h: int) -> np.ndarray:
    e = 1e-9
    xs = np.array([-1.0, -e, 0.0, e, 0.5, w / 2, w - 0.5, w - e, w, w + e, w + 1.0])
    ys = np.array([-1.0, -e, 0.0, e, 0.5, h / 2, h - 0.5, h - e, h, h + e, h + 1.0])
    grid = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
    bad = np.array([[np.nan, 1.0], [1.0, np.inf], [-np.inf, 0.0], [1e300, 1e300], [-1e300, 5.0]])
    return np.concatenate([grid, bad])


def extreme_directions() -> np.ndarray:
    e = 1e-12
    axes = np.concatenate([np.eye(3), -np.eye(3)])
    near = [[e, 0.0, -1.0], [-e, 0.0, -1.0], [0.0, 1.0, e], [0.0, -1.0, -e], [e, e, 1.0], [1.0, 0.0, e]]
    bad = [[0.0, 0.0, 0.0], [np.nan, 0.0, 1.0], [np.inf, 0.0, 1.0], [1e300, 1e300, 1e300], [1e-300, 0.0, 0.0]]
    return np.concatenate([axes, np.array(near), np.array(bad)])


@pytest.mark.parametrize("name", MODELS)
def test_every_model_stays_finite_at_its_extremes(name):
    for spec, size in REGISTRY.entry(name).examples:
        lens = make_lens(spec, size)
        pix = extreme_pixels(lens.width, lens.height)
        with np.errstate(all="raise"):  # a model must not even warn
            d, ok = lens.pixel_to_dir(pix)
            xy, ok2 = lens.dir_to_pixel(extreme_directions())
        for values, valid in ((d, ok), (xy, ok2)):
            assert valid.dtype == bool and np.isfinite(values).all(), spec
            assert not values[~valid].any(), spec  # zero where invalid
        assert not ok[-5:-1].any() and not ok2[-5:-2].any(), spec  # NaN, inf and zero are never rays
        assert np.allclose(np.linalg.norm(d[ok], axis=-1), 1.0, atol=1e-12), spec


def test_finding_the_models_and_building_one_leaves_numba_unimported():
    # the compiled twins live in *_kernels modules, which discovery skips and the models import on first
    # use: listing the models ('lenslab lenses') and building cameras stay quick
    import subprocess
    import sys

    code = ("import sys\nfrom lenslab.lenses import REGISTRY, make_lens\n"
            "[make_lens(spec, size) for e in REGISTRY.entries() for spec, size in e.examples[:1]"
            " if not spec.startswith('lensfun')]\n"
            "print(sorted(m for m in ('numba', 'cv2', 'scipy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
