"""Files warped at once share the batch's maps: each geometry's plan and maps are built once however the threads
interleave. The builder is held (an Event, never a sleep) until a second thread has asked for the same geometry and
is waiting for it, the interleaving where two builds used to happen; then one build serves both, and a build that
fails fails both files with its error."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import lenslab.warp.batch as batch
from lenslab.cli.main import main
from lenslab.errors import WarpError
from lenslab.io import write
from lenslab.lenses import Camera
from lenslab.warp import WarpPlan
from lenslab.warp.batch import PlanCache

WAIT = 60.0  # seconds before a test gives up on a state that never comes (a broken cache), not a timing


class _Held:
    """A plan builder (PlanCache's ``factory``) that holds the build of ``held`` sources until a second caller
    has asked for it: either waiting for the pending build (the cache's Future) or building it again."""

    def __init__(self, monkeypatch, held=lambda src: True, fail: Exception | None = None):
        self.calls = self.held_calls = 0
        self.asked = threading.Event()
        self.held, self.fail = held, fail
        self.lock = threading.Lock()
        outer = self

        class Watched(batch.Future):
            def result(self, timeout=None):
                if not self.done():
                    outer.asked.set()  # a second caller waits for the build in progress
                return super().result(timeout)

        monkeypatch.setattr(batch, "Future", Watched)

    def __call__(self, src, dst, **options):
        with self.lock:
            self.calls += 1
            self.held_calls += self.held(src)
            if self.held_calls > 1:
                self.asked.set()  # (a cache that builds again: let the first go, the count tells)
        if self.held(src):
            assert self.asked.wait(WAIT), "no second caller asked for the geometry"
        if self.fail is not None:
            raise self.fail
        return WarpPlan(src, dst, **options)


def _both(cache, src, dst):
    """``cache.plan(src, dst)`` on two threads at once: each thread's plan or exception."""
    got: list = [None, None]

    def ask(i):
        try:
            got[i] = cache.plan(src, dst)
        except Exception as exc:  # noqa: BLE001 - each thread's own failure, compared below
            got[i] = exc

    threads = [threading.Thread(target=ask, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(WAIT)
        assert not t.is_alive()
    return got


def test_two_threads_asking_for_one_geometry_build_its_maps_once(monkeypatch):
    src, dst = Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (24, 24))
    held = _Held(monkeypatch)
    cache = PlanCache(factory=held)
    first, second = _both(cache, src, dst)
    assert held.calls == 1 and cache.built == 1
    assert first is second and first._bands is not None  # the maps are computed, once, and shared
    ref = WarpPlan(src, dst, cache=True)
    ref.prepare()
    assert len(first._bands) == len(ref._bands)
    for got, want in zip(first._bands, ref._bands):  # the same taps as a plan made alone
        for name in ("off", "tx", "ty", "fold_idx", "fold_x", "fold_y"):
            np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    image = np.random.default_rng(5).random((32, 64, 3)).astype(np.float32)
    np.testing.assert_array_equal(first.run(image)[0], ref.run(image)[0])


@pytest.mark.parametrize("error", [MemoryError("no room for the maps"), WarpError("the lens sees nothing")])
def test_a_failed_build_fails_both_callers_and_is_tried_again(monkeypatch, error):
    src, dst = Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (24, 24))
    held = _Held(monkeypatch, fail=error)
    cache = PlanCache(factory=held)
    got = _both(cache, src, dst)
    assert held.calls == 1 and cache.built == 0
    assert all(type(e) is type(error) and str(e) == str(error) for e in got)
    assert got[0] is not got[1]  # each file's own failure (the funnel marks its file on it)
    held.fail = None  # the failure is not kept: the next file of this geometry builds it
    assert isinstance(cache.plan(src, dst), WarpPlan) and held.calls == 2 and cache.built == 1


def test_a_batch_of_two_sizes_on_two_threads_reports_two_maps(monkeypatch, tmp_path, capsys):
    rng = np.random.default_rng(7)
    paths = []
    for name, (w, h) in (("adobe", (64, 32)), ("sunset", (96, 48)), ("city", (96, 48))):
        paths.append(tmp_path / f"{name}.exr")
        write(paths[-1], rng.random((h, w, 3)).astype(np.float32), pixel_type="float")
    # the first file runs alone; the two of the second size run at once, the second asking while the first builds
    held = _Held(monkeypatch, held=lambda src: src.width == 96)
    monkeypatch.setattr("lenslab.warp.WarpPlan", held)
    rc = main(["warp", *map(str, paths), "-o", str(tmp_path / "wb5"), "--to", "fisheye:fov=180", "--size", "32x32",
               "--format", "jpg", "--jobs", "2"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "warped 3 of 3 file(s) with 2 map(s)" in err
    assert held.calls == 2 and held.asked.is_set()
    assert sorted(p.name for p in (tmp_path / "wb5").iterdir()) == ["adobe.jpg", "city.jpg", "sunset.jpg"]


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
