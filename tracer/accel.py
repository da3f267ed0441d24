"""Ray casts through embree (embreex, the engine behind trimesh's and pyvista's ray tracing).

The embree scene is built once per tracer scene and queried many times. Embree works in float32;
vertices are shifted so the scene's bounding-box centre is the origin (``centre=True``, or by the
caller, as :class:`~tracer.scene.Scene` does), which keeps float32 precision where the geometry is. Embree releases the GIL during a query, so large batches are split over a
thread pool.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

F32 = np.float32
MIN_CHUNK = 8192  # rays per thread below which splitting a batch costs more than it saves

_POOL: ThreadPoolExecutor | None = None


def cpu_count() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def pool() -> ThreadPoolExecutor:
    global _POOL
    if _POOL is None:
        _POOL = ThreadPoolExecutor(max_workers=cpu_count(), thread_name_prefix="tracer")
    return _POOL


class Accelerator:
    """An embree BVH over one triangle mesh; closest-hit and any-hit (shadow) queries."""

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, centre: bool = True):
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        v = np.asarray(vertices, dtype=np.float64)
        t = np.ascontiguousarray(triangles, dtype=np.int32)
        self.shift = 0.5 * (v.min(axis=0) + v.max(axis=0)) if (len(v) and centre) else np.zeros(3)
        self.n_triangles = len(t)
        self.scene = rtcore_scene.EmbreeScene()
        if len(t):
            TriangleMesh(scene=self.scene, vertices=np.ascontiguousarray(v - self.shift, dtype=F32), indices=t)
        # commit now (embreex commits on the first query), so build time is not charged to a render
        self.scene.run(np.zeros((1, 3), F32), np.array([[0, 0, 1]], F32))

    def _split(self, n: int, threads: int | None) -> list[slice]:
        threads = cpu_count() if threads is None else max(1, int(threads))
        k = max(1, min(threads, n // MIN_CHUNK))
        edges = np.linspace(0, n, k + 1).astype(int)
        return [slice(a, b) for a, b in zip(edges[:-1], edges[1:])]

    def _origins(self, origins: np.ndarray) -> np.ndarray:
        """Origins relative to the scene centre, float32, in one pass whatever the input precision."""
        origins = np.asarray(origins)
        if not self.shift.any():
            return np.ascontiguousarray(origins, dtype=F32)
        out = np.empty(origins.shape, dtype=F32)
        shift = self.shift.astype(origins.dtype) if origins.dtype in (np.float32, np.float64) else self.shift
        np.subtract(origins, shift, out=out, casting="unsafe")
        return out

    def intersect(self, origins: np.ndarray, dirs: np.ndarray, threads: int | None = None):
        """Closest hits: triangle index (int32, -1 for a miss) and distance (float32, inf for a miss).

        ``dirs`` need not be unit length; distances are in units of ``|dir|``.
        """
        n = len(origins)
        if n == 0:
            return np.empty(0, dtype=np.int32), np.empty(0, dtype=F32)
        o = self._origins(origins)
        d = np.ascontiguousarray(dirs, dtype=F32)
        parts = self._split(n, threads)
        if len(parts) == 1:
            r = self.scene.run(o, d, output=1)
            prim, dist = r["primID"], r["tfar"]
        else:
            prim = np.empty(n, dtype=np.int32)
            dist = np.empty(n, dtype=F32)

            def work(s: slice) -> None:
                r = self.scene.run(o[s], d[s], output=1)
                prim[s] = r["primID"]
                dist[s] = r["tfar"]

            list(pool().map(work, parts))
        np.copyto(dist, np.float32(np.inf), where=prim < 0)
        return prim, dist

    def occluded(self, origins: np.ndarray, dirs: np.ndarray, tmax: np.ndarray | float | None = None,
                 threads: int | None = None) -> np.ndarray:
        """True where something lies along the ray before ``tmax`` (in units of ``|dir|``)."""
        n = len(origins)
        out = np.zeros(n, dtype=bool)
        if n == 0:
            return out
        o = self._origins(origins)
        d = np.ascontiguousarray(dirs, dtype=F32)
        far = np.full(n, 1e37, dtype=F32) if tmax is None else np.array(np.broadcast_to(tmax, (n,)), dtype=F32)
        far = np.minimum(far, F32(1e37))

        def work(s: slice) -> None:
            out[s] = self.scene.run(o[s], d[s], dists=np.ascontiguousarray(far[s]), query="OCCLUDED") != -1

        parts = self._split(n, threads)
        if len(parts) == 1:
            work(parts[0])
        else:
            list(pool().map(work, parts))
        return out
