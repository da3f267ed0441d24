"""The pyramid a warp builds lazily (only the rows of the coarser levels that footprints read) gives the
footprint filter exactly the texels of the pyramid built whole, and leaves the rest unbuilt.

The whole pyramid is itself held to 2x2 means computed in float64 (tests/warp/test_footprint_exact.py), so the
lazy one is held to the same values: any row the filter reads but the lazy pyramid did not build would be
uninitialised memory, and the outputs would differ."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp import antialias as aa
from lenslab.warp.engine import WarpPlan
from lenslab.warp.pyramid import pyramid
from lenslab.warp.seam import Border

W, H = 256, 128


def _source(seed=0):
    rng = np.random.default_rng(seed)
    img = rng.uniform(0.0, 1.0, (H, W, 3)).astype(np.float32)
    img[::17, ::13] = 500.0  # small bright texels, as a sun or a lamp
    return img


@pytest.mark.parametrize("spec", ["fisheye:fov=180", "fisheye:fov=360", "equirect"])
def test_lazy_pyramid_gives_the_whole_pyramids_output(spec):
    img = _source(1)
    src = Camera.from_spec("equirect", (W, H))
    size = (16, 8) if spec == "equirect" else (64, 64)  # the equirect: every footprint 16 texels, on level 1
    plan = WarpPlan(src, Camera.from_spec(spec, size), antialias=True)
    bands = list(plan.bands())
    outs = []
    for lazy in (False, True):
        pyr = pyramid(img, plan.border, lazy=lazy)
        out = np.zeros(plan.out_shape + (3,), np.float32)
        alpha = np.zeros(plan.out_shape, np.float32)
        for b in bands:
            aa.sample_footprint(pyr, b, plan.border, out[b.r0:b.r1], alpha[b.r0:b.r1])
        outs.append((out, alpha, pyr))
    np.testing.assert_array_equal(outs[1][0], outs[0][0])
    np.testing.assert_array_equal(outs[1][1], outs[0][1])
    built = outs[1][2].built
    assert any(d.any() for d in built)  # the coarser levels were read
    if spec == "fisheye:fov=180":  # a hemisphere reads the coarser levels near the poles only
        assert sum(int(d.sum()) for d in built) < sum(len(d) for d in built) // 2


def test_a_warp_with_antialias_builds_the_rows_it_reads():
    """The warp itself (lazy) against the footprint filter over the whole pyramid."""
    img = _source(2)
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec("fisheye:fov=200", (48, 48))
    out, alpha = WarpPlan(src, dst, antialias=True).run(img)
    plan = WarpPlan(src, dst, antialias=True)
    pyr = pyramid(img, plan.border)
    want = np.zeros_like(out)
    want_alpha = np.zeros_like(alpha)
    for b in plan.bands():
        aa.sample_footprint(pyr, b, plan.border, want[b.r0:b.r1], want_alpha[b.r0:b.r1])
    np.testing.assert_array_equal(alpha, want_alpha)
    np.testing.assert_array_equal(out, want)


def test_level_rows_kernel_matches_its_numpy_reference():
    """The rows each level's footprints read, compiled and in NumPy (float32 sides as the filter clamps them:
    NaN a point, beyond 2^40 at 2^40), on footprints from a texel to the whole panorama, hostile ones included."""
    from lenslab import cxx_kernels as K
    from lenslab.warp.kernels import reference as ref
    from lenslab.warp.pyramid import MAX_TAPS

    rng = np.random.default_rng(5)
    pyr = pyramid(np.zeros((512, 1024, 1), np.float32), Border(True, True, True), lazy=True)
    n = 4000
    ys = rng.uniform(-40.0, 560.0, n).astype(np.float32)
    side = np.exp(rng.uniform(np.log(0.5), np.log(2000.0), (n, 4))) * rng.choice([-1.0, 1.0], (n, 4))
    foot = side.astype(np.float32)
    foot[:10] = np.nan
    foot[10:20, 1] = np.inf
    ys[20:30] = np.nan
    valid = rng.uniform(size=n) > 0.2
    rows = np.empty((len(pyr.shapes), 2), np.int64)
    K.level_rows(pyr.shapes, ys, valid, foot, MAX_TAPS, rows)
    want = ref.level_rows(pyr.shapes, ys, valid, foot)
    np.testing.assert_array_equal(rows, want)
    assert (rows[1:, 0] < rows[1:, 1]).sum() >= 5  # footprints on several coarser levels


@pytest.mark.parametrize("far", [5.0 * H, -4.0 * H, float("nan")])
def test_a_window_wholly_beyond_an_edge_reads_built_rows(far):
    # A valid sample whose window lies wholly beyond the top or bottom (or a NaN row, read as far above) is
    # clamped by level_rows to an empty range, while the filter still reads the edge rows it folds to: the
    # lazy pyramid must build them (before, the lazy output was the unbuilt buffer: NaN here).
    from lenslab.warp.kernels import native
    from lenslab.warp.pyramid import MAX_TAPS

    img = _source(3)
    n = 4
    xs = np.full((1, n, 1), 10.0, np.float32)
    ys = np.full((1, n, 1), far, np.float32)
    valid = np.ones((1, n, 1), bool)
    foot = np.tile(np.array([30.0, 0.0, 0.0, 30.0], np.float32), (1, n, 1, 1))  # 30 texels: level 2
    outs = []
    for lazy in (False, True):
        pyr = pyramid(img, Border(), lazy=lazy)
        if lazy:
            pyr.rest[:] = np.nan  # what an unbuilt row would hold at worst
        pyr.ensure(ys, valid, foot)
        out = np.empty((n, 3), np.float32)
        alpha = np.empty(n, np.float32)
        native.kernels().footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, xs, ys, valid, foot,
                                   False, False, False, MAX_TAPS, out, alpha)
        outs.append(out)
    assert np.isfinite(outs[0]).all()
    np.testing.assert_array_equal(outs[1], outs[0])
