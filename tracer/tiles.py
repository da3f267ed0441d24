"""One image traced as tiles of rows on the workers of a Dask cluster, bit for bit the local render.

A tile is a run of whole bands of :func:`tracer.rendering.render`: each band draws its random numbers
from a generator seeded by ``(seed, pass, first row)`` and its sub-pixel positions row by row, so a
tile's pixels are exactly those of the whole image, whatever the number of tiles or workers.

Scenes are never sent over the network: each worker loads the scene (and builds its embree structure)
once, on its first tile, and keeps it for every later tile of that scene (:func:`worker_scene`).
Only the scene's name or path, the camera and the tile's rows travel; the pixels come back.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

_SCENES: dict[tuple, object] = {}  # one per worker process: scene key -> loaded scene
_KEEP_SCENES = 2
#: tiles per worker thread by default: the rows of an image are not equally costly (an interior's
#: panorama: walls near, light far) and a worker's last tile may end while the other's has far to go;
#: with 16 a tile is about 1/16 of a worker's share, so the wait at the end is about 1/64 of the render
#: on average, against the scheduler's cost of a task (a few ms) per tile (docs/design.md, "Clusters: scaling")
TILES_PER_THREAD = 16


def scene_key(scene: str, env: str | None = None) -> tuple:
    """What identifies a scene: its name or absolute path with the file's size and time, and the panorama."""
    def stamp(path):
        if path and os.path.exists(path):
            st = os.stat(path)
            return (os.path.abspath(path), st.st_size, st.st_mtime_ns)
        return path

    return (stamp(scene), stamp(env))


def worker_scene(scene: str, env: str | None = None, prepare: tuple | None = None):
    """The scene loaded once in this process (the accelerator built on first use), then reused.

    ``prepare``: ``(function, args)`` applied to the loaded scene before use, ``function(scene, *args)``
    (a module-level function: it travels by name), e.g. to move its lights as a validation source does.
    """
    key = scene_key(scene, env) + ((prepare[0].__module__, prepare[0].__qualname__, tuple(prepare[1])),) \
        if prepare else scene_key(scene, env)
    if key not in _SCENES:
        from tracer.load import load_scene

        loaded = load_scene(scene, **({"env": env} if env else {}))
        if prepare:
            prepare[0](loaded, *prepare[1])
        loaded.accel  # build the embree structure here, on the worker, once
        while len(_SCENES) >= _KEEP_SCENES:
            _SCENES.pop(next(iter(_SCENES)))
        _SCENES[key] = loaded
    return _SCENES[key]


def render_tile(scene: str, env: str | None, camera, rows: tuple[int, int], options: dict,
                prepare: tuple | None = None) -> dict:
    """Trace ``rows`` of the image on this worker; returns the tile's float32 arrays."""
    from lenslab.cluster.tasks import worker_threads
    from tracer.process import prepare_worker
    from tracer.rendering import render

    prepare_worker()  # freed memory kept, as in a render's own process
    result = render(worker_scene(scene, env, prepare), camera, rows=rows, threads=worker_threads(), **options)
    return {"rows": rows, "image": result.image, "variance": result.variance, "alpha": result.alpha,
            "scene": result.info.get("scene", "")}


def tile_rows(camera, spp: int, tiles: int, batch: int | None = None) -> list[tuple[int, int]]:
    """Row ranges of at most ``tiles`` tiles, each a run of whole bands, as even as the bands allow."""
    from tracer.rendering import DEFAULT_BATCH, band_rows

    rows = band_rows(camera.width, spp, batch or DEFAULT_BATCH)
    bands = -(-camera.height // rows)
    n = max(1, min(int(tiles), bands))
    edges = [round(i * bands / n) * rows for i in range(n + 1)]
    edges[-1] = camera.height
    return [(a, min(b, camera.height)) for a, b in zip(edges[:-1], edges[1:]) if a < b]


def render_tiled(client, scene: str, camera, spp: int = 16, seed: int | None = 0, integrator: str = "path",
                 max_depth: int = 8, tiles: int | None = None, env: str | None = None, progress: bool = False,
                 prepare: tuple | None = None):
    """Render ``camera``'s image of ``scene`` as tiles on ``client``'s workers; a
    :class:`~tracer.rendering.RenderResult` equal, pixel for pixel, to ``render(scene, camera, ...)``.

    ``tiles`` defaults to :data:`TILES_PER_THREAD` per worker thread; ``prepare`` see :func:`worker_scene`. A worker lost mid-render has its tiles traced again
    elsewhere (by the scheduler); Ctrl-C cancels the tiles not done.
    """
    from lenslab.cluster.run import gather_as_completed, submit
    from tracer.rendering import RenderResult, relative_error

    if tiles is None:
        tiles = TILES_PER_THREAD * max(1, sum(client.nthreads().values()))
    ranges = tile_rows(camera, spp, tiles)
    options = {"spp": int(spp), "seed": seed, "integrator": integrator, "max_depth": int(max_depth)}
    start = time.perf_counter()
    futures = [submit(client, render_tile, scene, env, camera, r, options, prepare, name="tracer-tile")
               for r in ranges]
    height, width = camera.height, camera.width
    image = np.empty((height, width, 3), dtype=np.float32)
    variance = np.empty((height, width, 3), dtype=np.float32)
    alpha = np.empty((height, width), dtype=np.float32)
    workers: dict[str, list] = {}
    name = os.path.basename(str(scene))
    for _, out, worker, seconds, error in gather_as_completed(client, futures, progress=progress, unit="tile",
                                                               desc=f"tracing {name} in {len(ranges)} tiles"):
        if error is not None:
            client.cancel(futures, force=True)
            raise RuntimeError(f"a tile failed on the cluster: {error}")
        a, b = out["rows"]
        image[a:b], variance[a:b], alpha[a:b] = out["image"], out["variance"], out["alpha"]
        w = workers.setdefault(worker, [0, 0.0])
        w[0] += 1
        w[1] += seconds
        scene_name = out["scene"]
    seconds = time.perf_counter() - start
    return RenderResult(image=image, variance=variance, alpha=alpha, spp=int(spp), seconds=seconds, camera=camera,
                        integrator=integrator, max_depth=max_depth, seed=seed, stopped_by="spp",
                        info={"samples_per_second": spp * width * height / max(seconds, 1e-12),
                              "scene": scene_name, "tiles": len(ranges),
                              "workers": {k: {"tiles": v[0], "seconds": round(v[1], 3)} for k, v in workers.items()},
                              "relative_error": relative_error(image, variance)})


def render_on_cluster(args, camera):
    """``tracer render --scheduler ADDRESS [--tiles N]``: the render on the cluster, with a line per worker;
    None when no scheduler is given (the render then runs here)."""
    import sys

    from lenslab.errors import UsageError
    from lenslab.cluster import scheduler_address
    from lenslab.cluster.connect import client_for

    where = scheduler_address(args)
    if where is None:
        if args.tiles:
            raise UsageError("--tiles splits a render over a Dask cluster: give --scheduler ADDRESS too")
        return None
    if args.time_budget is not None or args.target_error is not None:
        raise UsageError("--time-budget and --target-error need the whole image in one place; "
                         "render on the cluster with a fixed --spp")
    # workers have their own working folder: a scene or panorama file goes by its absolute path
    scene = os.path.abspath(args.scene) if os.path.exists(args.scene) else args.scene
    env = os.path.abspath(args.env) if args.env else None
    with client_for(where, getattr(args, "scheduler_timeout", None)) as client:
        result = render_tiled(client, scene, camera, spp=args.spp, seed=args.seed, integrator=args.integrator,
                              max_depth=args.max_depth, tiles=args.tiles, env=env, progress=not args.quiet)
        address = client.scheduler.address
    if not args.quiet:
        print(f"tracer render: {result.info['tiles']} tiles on the cluster at {address}", file=sys.stderr)
        for who, w in sorted(result.info["workers"].items()):
            print(f"  {who}: {w['tiles']} tile(s), {w['seconds']:.2f} s", file=sys.stderr)
    return result


def attach_cluster(source, args) -> None:
    """``lenslab validate --scheduler``: the tracer source renders its images as tiles on the cluster
    (the same pixels as here); the client closes when the source is dropped or the program ends."""
    import weakref

    from lenslab.cluster import scheduler_address
    from lenslab.cluster.connect import client_for

    where = scheduler_address(args)
    if where is None:
        return
    if not hasattr(source, "scene_name"):  # a closed-form source: nothing to trace, nothing to send
        print(f"lenslab validate: note: --scene {args.scene} is computed, not traced; the cluster is not used",
              file=sys.stderr)
        return
    connection = client_for(where, getattr(args, "scheduler_timeout", None))
    source.client = connection.__enter__()
    weakref.finalize(source, connection.__exit__, None, None, None)


__all__ = ["render_tiled", "render_on_cluster", "attach_cluster", "render_tile", "tile_rows", "worker_scene"]
