"""The engine's band runner and its per-band output checks hold to their plain definitions: ``run_bands`` is
``[work(j) for j in jobs]`` (results and ``on_done`` in job order, first error raised), and the checks the bands
make are NumPy's own reductions over the whole output."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.warp.checks import OutputChecks
from lenslab.warp.kernels.dispatch import run_bands, set_threads


@pytest.fixture(params=[1, 2, 3])
def threads(request):
    set_threads(request.param)
    yield request.param
    set_threads(None)


@given(st.lists(st.integers(-1000, 1000), max_size=40))
@settings(max_examples=30, deadline=None)
def test_results_and_on_done_come_in_job_order(jobs):
    for n in (1, 2, 3):
        set_threads(n)
        try:
            seen = []
            out = run_bands(jobs, lambda j: j * j - 3, lambda r: seen.append((threading.get_ident(), r)))
        finally:
            set_threads(None)
        assert out == [j * j - 3 for j in jobs]
        assert [r for _, r in seen] == out
        assert {t for t, _ in seen} <= {threading.get_ident()}  # on_done runs in the calling thread


def test_the_first_error_is_raised_after_the_started_jobs_finish(threads):
    started, finished = [], []
    third_started = threading.Event()

    def work(j):
        started.append(j)
        if j == 3:
            third_started.set()
            raise ValueError("band 3")
        if j == 2 and threads > 1:
            third_started.wait(30)  # on another thread: job 2 is still running when job 3 fails
        finished.append(j)
        return j

    with pytest.raises(ValueError, match="band 3"):
        run_bands(range(40), work)
    assert 2 in finished and set(finished) == set(started) - {3}  # no job is left running


def test_a_job_that_runs_bands_runs_them_in_its_own_thread(threads):
    def inner(j):
        ident = threading.get_ident()
        return run_bands(range(4), lambda k: (threading.get_ident() == ident, j * 10 + k))

    out = run_bands(range(6), inner)
    assert out == [[(True, j * 10 + k) for k in range(4)] for j in range(6)]


def _bands(out, alpha, rows, image_alpha):
    checks = OutputChecks(image_alpha)
    for r in range(0, out.shape[0], rows):
        checks.band(out[r:r + rows], alpha[r:r + rows])
    return checks


values = st.sampled_from([0.0, 0.25, 1.0, -0.5, 1.5, 3e38, np.inf, -np.inf, np.nan])


@given(st.lists(values, min_size=3, max_size=12), st.integers(1, 5), st.booleans(), st.integers(0, 2**32 - 1))
@settings(max_examples=60, deadline=None)
def test_band_checks_agree_with_numpy_over_the_whole_output(special, rows, image_alpha, seed):
    rng = np.random.default_rng(seed)
    out = rng.random((7, 5, 4)).astype(np.float32)
    alpha = rng.random((7, 5)).astype(np.float32)
    for v in special:  # a few values of every kind, anywhere (colour, the image's alpha, coverage)
        i, j, c = rng.integers(7), rng.integers(5), rng.integers(5)
        if c == 4:
            alpha[i, j] = v
        else:
            out[i, j, c] = v
    checks = _bands(out, alpha, rows, image_alpha)
    a = out[..., -1]
    assert checks.finite == bool(np.isfinite(out).all())
    in_range = bool(np.all((alpha >= 0) & (alpha <= 1))) and (not image_alpha or bool(np.all((a >= 0) & (a <= 1))))
    assert checks.in_range == in_range
    if in_range:
        assert checks.covered == bool(alpha.any())


@pytest.mark.parametrize("channels", [3, 4])
def test_a_warp_settles_its_output_as_settle_does_over_the_whole_output(threads, channels):
    """Bicubic overshoot next to a hard alpha edge takes alpha past 1 and colour below 0: the warp's output is
    its bands' output settled by lenslab.io.alpha.settle over the whole image."""
    from lenslab.io.alpha import settle
    from lenslab.lenses import Camera
    from lenslab.warp import WarpPlan

    rng = np.random.default_rng(5)
    img = rng.random((64, 128, channels)).astype(np.float32) * 4.0
    img[:, ::9] = -2.0  # sharp edges: Catmull-Rom's lobes overshoot on both sides
    if channels == 4:
        img[..., 3] = (np.arange(128) % 7 < 3)[None, :]  # hard-edged alpha: overshoot past 1 and below 0
    plan = WarpPlan(Camera.from_spec("equirect", (128, 64)), Camera.from_spec("fisheye:fov=200", (96, 96)),
                    filter="bicubic")
    out, alpha = plan.run(img)
    raw, cov = np.zeros_like(out), np.zeros_like(alpha)
    plan.render(plan.check_image(img), raw, cov)
    if channels == 4:
        assert raw[..., 3].max() > 1.0 and raw[..., 3].min() < 0.0  # the case settle exists for
    settle(raw, cov)
    np.testing.assert_array_equal(out, raw)
    np.testing.assert_array_equal(alpha, cov)


def test_a_view_that_sees_nothing_warns(threads):
    from lenslab.lenses import Camera, Pose
    from lenslab.warp import warp
    from lenslab.warp.engine import EmptyViewWarning

    src = Camera.from_spec("fisheye:fov=90", (64, 64))
    dst = Camera(Camera.from_spec("perspective:fov=60", (32, 32)).lens, Pose.from_ypr(180, 0, 0))  # behind it
    with pytest.warns(EmptyViewWarning):
        out, alpha = warp(np.ones((64, 64, 3), np.float32), src, dst)
    assert not alpha.any() and not out.any()
