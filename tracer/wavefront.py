"""The path tracer's bounce loop in compiled passes, for Lambertian scenes lit by area lights.

:func:`trace` gives the same radiance, bit for bit, as :func:`tracer.integrators.trace` with
``integrator="path"`` (the NumPy steps stay there as the reference, and tests compare the two): it
draws the same random numbers in the same order and does the same float32 operations per path. Per
bounce Python makes three calls into the C++ passes of ``lenslab.cxx_kernels.LambertScene``
(``src/native/tracer_paths.cpp``): the closest hits (embree's C API called per ray,
:mod:`tracer.embree_api`), one pass that shades every hit (emission with its MIS weight, a light sample,
the continuation, Russian roulette), and one that casts the shadow rays, adds the visible light and
retires finished paths. The live paths stay in a few float32 arrays updated in place. The passes run on
the calling thread with the GIL released: a render runs its bands on several threads.
"""

from __future__ import annotations

import threading
import weakref

import numpy as np

F32 = np.float32
TWO_PI = 2 * np.pi

_RTC: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # accelerator -> (its passes, their embree scene)
_RTC_LOCK = threading.Lock()


def passes(scene):
    """The compiled passes of ``scene`` (``lenslab.cxx_kernels.LambertScene``): its triangles, materials and
    lights, and an embree scene of its own (:class:`tracer.embree_api.RtcScene`: the same triangles as
    ``scene.accel`` in the same float32 frame); built once per accelerator."""
    with _RTC_LOCK:
        accel = scene.accel
        found = _RTC.get(accel)
        if found is None:
            from lenslab.cxx_kernels import LAMBERT_PACKET, LambertScene

            from tracer.embree_api import RtcScene, entry_points

            rtc = RtcScene((scene.vertices - scene.shift).astype(F32), scene.triangles)
            t = scene.table
            lights = scene.light_dist is not None  # without area lights the passes only cast rays
            cdf = scene.light_dist.cdf if lights else np.zeros(0)
            light_tris = scene.light_triangles if lights else np.zeros(0, np.int64)
            lam = LambertScene(rtc.handle, *entry_points(LAMBERT_PACKET), scene.normals, scene.material_ids,
                               scene.emissive, t.two_sided, scene.light_area_pdf, t.emission, t.kd, cdf, light_tris,
                               scene.v0, scene.e1, scene.e2)
            found = _RTC[accel] = (lam, rtc)  # the passes hold the scene's pointer: keep the scene alive with them
        return found[0]


def applies(scene, integrator: str) -> bool:
    """Whether the compiled bounce loop covers this scene and integrator: path tracing, Lambertian materials,
    area lights, and neither an environment nor point lights (and embree's library and the passes at hand)."""
    if not (integrator == "path" and scene.table.lambertian_only and scene.has_area_lights
            and scene.environment is None and len(scene.point_light_pos) == 0):
        return False
    from tracer.embree_api import available

    return available() and native()


def native() -> bool:
    """Whether the compiled passes were built (``pip install -e .``; else the NumPy steps do the work)."""
    try:
        from lenslab.cxx_kernels import LambertScene  # noqa: F401
    except ImportError:
        return False
    return True


def trace(scene, o: np.ndarray, d: np.ndarray, rng: np.random.Generator, max_depth: int, rr_depth: int,
          threads: int | None, out: np.ndarray) -> np.ndarray:
    """Radiance along rays from ``o`` (float32, the scene's local frame) along unit ``d`` (float32) into
    ``out`` (float32 ``(N, 3)``, zeros); see :func:`tracer.integrators.trace`."""
    lam = passes(scene)
    eps = F32(scene.epsilon)
    eps2 = F32(2 * eps)
    p_area = F32(1)  # only area lights: every light sample goes to them
    n = len(o)
    prim, t = np.empty(n, dtype=np.int32), np.empty(n, dtype=F32)
    idx = np.arange(n)
    o = o.copy()  # the state is updated in place, bounce after bounce
    d = d.copy()
    beta = np.ones((n, 3), dtype=F32)
    L = np.zeros((n, 3), dtype=F32)
    prev_pdf = np.zeros(n, dtype=F32)
    specular = np.ones(n, dtype=bool)  # camera rays: emitters seen directly take no MIS weight
    # the shadow rays of a bounce (at most one per path) and which paths go on
    alive = np.empty(n, dtype=bool)
    sh_rows = np.empty(n, dtype=np.int64)
    sh_o, sh_d, sh_val = (np.empty((n, 3), dtype=F32) for _ in range(3))
    sh_t = np.empty(n, dtype=F32)
    none2, none1 = np.zeros((0, 4), F32), np.zeros(0, F32)
    depth = 0
    while n:
        lam.intersect(o, d, n, prim, t)  # closest hits, in the kernel: embree's own answers
        prim_n, t_n = prim[:n], t[:n]
        last = depth >= max_depth
        m = 0 if last else int(np.count_nonzero(prim_n >= 0))
        u_nee, u_bsdf, cphi, sphi, u_rr = none2, none2, none1, none1, none1
        if m:  # the random numbers of the NumPy steps, in their order
            u_nee = rng.random((m, 4), dtype=F32)
            u_bsdf = rng.random((m, 3), dtype=F32)
            phi = TWO_PI * u_bsdf[:, 2]
            cphi, sphi = np.cos(phi), np.sin(phi)
            if depth + 1 >= rr_depth:
                u_rr = rng.random(m, dtype=F32)
        m, g = lam.shade(prim_n, t_n, o, d, beta, L, prev_pdf, specular, idx, out, u_nee, u_bsdf, cphi, sphi, u_rr,
                         p_area, eps, eps2, last, depth + 1 >= rr_depth, alive, sh_rows, sh_o, sh_d, sh_t, sh_val)
        if last or not m:
            break
        n = lam.settle(m, idx, o, d, beta, L, prev_pdf, alive, g, sh_rows, sh_o, sh_d, sh_t, sh_val, out)
        if depth == 0:
            specular[:] = False
        depth += 1
    return out
