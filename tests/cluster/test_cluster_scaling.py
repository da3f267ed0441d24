"""What lets two workers trace an image in half the time of one: each worker keeps the memory its tiles
free (as a render's own process does), and an image is cut into enough tiles that neither worker waits
long for the other at the end. States, read back from outside the code that sets them; no timing.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys

import numpy as np
import pytest

pytest.importorskip("distributed")

pytestmark = pytest.mark.slow

BLOCK = 24 << 20  # bytes: above glibc's default mmap threshold (128 KiB), below the tracer's (32 MiB)


class _Mallinfo2(ctypes.Structure):
    """glibc's ``struct mallinfo2`` (malloc.h): ten size_t fields, summed over every arena."""

    _fields_ = [(name, ctypes.c_size_t) for name in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks",
                 "keepcost")]


def _glibc():
    libc = ctypes.CDLL(None)
    if not hasattr(libc, "mallinfo2"):  # pragma: no cover - glibc before 2.33, musl, macOS
        return None
    libc.mallinfo2.restype = _Mallinfo2
    libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
    libc.free.argtypes = [ctypes.c_void_p]
    return libc


def probe_malloc() -> dict:
    """On a worker: where glibc puts a block of :data:`BLOCK` bytes, as its own ``mallinfo2`` says:
    ``mmapped`` (the block has pages of its own, returned when freed) and ``kept`` (after it is freed, the
    arenas still hold at least that many free bytes: nothing was given back to the system)."""
    libc = _glibc()
    before = libc.mallinfo2()
    block = libc.malloc(BLOCK)
    ctypes.memset(block, 1, BLOCK)  # touched: its pages are faulted in
    held = libc.mallinfo2()
    libc.free(block)
    after = libc.mallinfo2()
    return {"mmapped": held.hblkhd - before.hblkhd >= BLOCK, "kept": after.fordblks >= BLOCK}


needs_glibc = pytest.mark.skipif(not sys.platform.startswith("linux") or _glibc() is None,
                                 reason="glibc's mallinfo2 reads the allocator's state (Linux)")


@contextlib.contextmanager
def _environment_restored():
    """This process's environment as it was: a Dask nanny also writes its workers' variables
    (``MALLOC_TRIM_THRESHOLD_``, ``OMP_NUM_THREADS``...) into the environment of the process that runs it."""
    saved = dict(os.environ)
    try:
        yield
    finally:
        os.environ.clear()
        os.environ.update(saved)


@needs_glibc
@pytest.mark.filterwarnings("ignore:Port .* is already in use")  # another cluster's status page: nothing to report
def test_a_worker_keeps_the_memory_its_tiles_free_whatever_dasks_nanny_set():
    """A plain Dask cluster (Dask's own worker settings: ``MALLOC_TRIM_THRESHOLD_=65536``, which also
    fixes the mmap threshold at 128 KiB): before its first tile a worker maps a 24 MiB block and gives it
    back on free; after a tile it serves it from its heap and keeps it."""
    from distributed import Client, LocalCluster

    from lenslab.lenses import Camera
    from tracer.tiles import render_tile

    with _environment_restored(), LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                               dashboard_address=None, silence_logs=40) as cluster, \
            Client(cluster, set_as_default=False) as client:
        env = client.run(os.environ.get, "MALLOC_TRIM_THRESHOLD_")
        assert list(env.values()) == ["65536"]  # Dask's default, as a user's `dask worker` has it
        (before,) = client.run(probe_malloc).values()
        assert before == {"mmapped": True, "kept": False}
        camera = Camera.from_spec("equirect", (32, 16))
        options = {"spp": 1, "seed": 0, "integrator": "path", "max_depth": 2}
        tile = client.submit(render_tile, "cornell", None, camera, (0, 8), options, pure=False).result()
        assert tile["image"].shape == (8, 32, 3)
        (after,) = client.run(probe_malloc).values()
        assert after == {"mmapped": False, "kept": True}


def _coverage(ranges, height: int) -> np.ndarray:
    """How many tiles hold each row (an independent count: every row, one by one)."""
    count = np.zeros(height, dtype=int)
    for a, b in ranges:
        count[a:b] += 1
    return count


@pytest.mark.parametrize("size,spp,band", [((2048, 1024), 64, 1), ((512, 300), 16, 8), ((64, 256), 1, 8)])
def test_the_default_tiles_of_two_workers_cover_the_image_once_in_whole_bands(size, spp, band):
    """16 tiles per worker thread: 32 for two single-threaded workers, each a run of whole bands, every row
    in exactly one. ``band`` is the band height written out from the rule (131072 samples per band, at
    most 8 rows): 131072 / (2048 * 64) = 1 row, 131072 / (512 * 16) = 16 -> 8, 131072 / 64 -> 8."""
    from lenslab.lenses import Camera
    from tracer.tiles import TILES_PER_THREAD, tile_rows

    camera = Camera.from_spec("equirect", size)
    ranges = tile_rows(camera, spp, TILES_PER_THREAD * 2)
    height = size[1]
    assert len(ranges) == 32
    assert np.array_equal(_coverage(ranges, height), np.ones(height, dtype=int))
    assert all(a % band == 0 for a, _ in ranges) and ranges[-1][1] == height
    bands = [-(-(b - a) // band) for a, b in ranges]  # the last band of an image may be short
    assert max(bands) - min(bands) <= 1  # as even as whole bands allow


def test_a_render_on_two_workers_is_cut_into_32_tiles_shared_between_them():
    """The default on a real cluster: 32 tiles for two single-threaded workers, every one rendered once
    (the workers' counts add up), both workers used, and the pixels those of the local render."""
    from lenslab.cluster.connect import local_cluster
    from lenslab.lenses import Camera
    from tracer.load import load_scene
    from tracer.rendering import render
    from tracer.tiles import render_tiled

    camera = Camera.from_spec("equirect", (64, 256))  # 32 bands of 8 rows at 1 spp
    with local_cluster(workers=2, threads=1) as client:
        tiled = render_tiled(client, "cornell", camera, spp=1, seed=5, max_depth=2)
    assert tiled.info["tiles"] == 32
    assert sum(w["tiles"] for w in tiled.info["workers"].values()) == 32
    assert len(tiled.info["workers"]) == 2
    local = render(load_scene("cornell"), camera, spp=1, seed=5, max_depth=2, threads=1)
    assert np.array_equal(tiled.image, local.image)


def _background_periods(dask_worker) -> dict:
    """A worker's periodic work, as its event loop runs it: milliseconds between calls."""
    return {name: dask_worker.periodic_callbacks[name].callback_time for name in ("profile", "tick")}


def test_lenslabs_workers_wake_their_profiler_every_100ms_and_the_docs_recipe_does_the_same(tmp_path):
    """lenslab's local workers sample their task's stack every 100 ms and check their event loop every
    200 ms (Dask's defaults: 10 ms and 20 ms), read back from the workers' event loops; the config file of
    docs/guide/batches.md and the README give `dask worker` the same settings as lenslab's own clusters."""
    import re
    from pathlib import Path

    import dask

    from lenslab.cluster.connect import WORKER_CONFIG, local_cluster

    with local_cluster(workers=2, threads=1) as client:
        periods = list(client.run(_background_periods).values())
    assert periods == [{"profile": 100.0, "tick": 200.0}] * 2
    for page in (Path(__file__).parents[2] / "docs" / "guide" / "batches.md", Path(__file__).parents[2] / "README.md"):
        recipe = re.search(r"```yaml\n(distributed:\n.*?)```", page.read_text(), re.S).group(1)
        folder = tmp_path / page.stem
        folder.mkdir()
        (folder / "lenslab.yaml").write_text(recipe)
        config = dask.config.merge(dask.config.config, dask.config.collect(paths=[str(folder)], env={}))
        with dask.config.set(config):
            for key, value in WORKER_CONFIG.items():
                assert dask.config.get(key) == value, (page.name, key)
    assert dask.config.get("distributed.worker.profile.interval") == "10ms"  # Dask's default, for contrast
