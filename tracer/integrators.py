"""Light transport, wavefront style: every step works on whole arrays of paths at once.

Depth counts scattering events: ``max_depth = 0`` sees emitters only, ``1`` is direct lighting,
``k`` allows paths of up to ``k`` bounces between the camera and a light.

- ``path``: unidirectional path tracing. At every non-specular vertex a light is sampled (next-event
  estimation to area lights, point lights and the environment, with a shadow ray) and the BSDF is
  sampled to continue the path; both strategies are combined by multiple importance sampling with
  Veach's power heuristic, so hitting an emitter by BSDF sampling adds its radiance with the
  complementary weight. Russian roulette from ``rr_depth`` on keeps the estimator unbiased.
- ``direct``: emission seen directly (also through mirrors) plus light sampling only at the first
  non-specular surface. It estimates the same quantity as ``path`` with ``max_depth = 1`` in scenes
  without mirrors, by a different strategy. With point lights and a fixed sample grid it is exact
  and noise-free.

Radiance in, radiance out: ``trace`` returns float32 ``(N, 3)`` radiance along each ray.
"""

from __future__ import annotations

import numpy as np

from tracer.materials import MIRROR
from tracer.sampling import F32, dot, power_heuristic, take, uniform_triangle

INTEGRATORS = ("path", "direct")
#: compiled passes (tracer.kernels): next-event estimation to area lights at Lambertian points, and the
#: whole bounce loop of path tracing in Lambertian scenes lit by area lights (tracer.wavefront);
#: False runs the NumPy steps, which give the same image
FUSED = True


def _light_choice(scene) -> tuple[float, float]:
    """Probabilities of sampling the area lights and the environment in next-event estimation."""
    area = scene.has_area_lights
    env = scene.environment is not None
    if area and env:
        return 0.5, 0.5
    return (1.0 if area else 0.0), (1.0 if env else 0.0)


def trace(scene, origins: np.ndarray, dirs: np.ndarray, rng: np.random.Generator, integrator: str = "path",
          max_depth: int = 8, rr_depth: int = 3, threads: int | None = 1) -> np.ndarray:
    """Radiance arriving at ``origins`` (world) from ``dirs`` (unit), float32 ``(N, 3)``."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"unknown integrator {integrator!r}; use one of {', '.join(INTEGRATORS)}")
    if max_depth < 0:
        raise ValueError(f"max_depth must be >= 0, got {max_depth}")
    mis = integrator == "path"
    n_rays = len(origins)
    out = np.zeros((n_rays, 3), dtype=F32)
    if n_rays == 0:
        return out
    accel = scene.accel
    table = scene.table
    env = scene.environment
    p_area, p_env = _light_choice(scene)
    eps = F32(scene.epsilon)
    has_mirror = table.has["mirror"]

    # state of the live paths; each path's radiance ``L`` travels with it and is written to ``out``
    # when the path ends (cheaper than scattering into ``out`` at every bounce)
    o = np.empty((n_rays, 3), dtype=F32)
    np.subtract(origins, scene.shift, out=o, casting="unsafe")  # into the scene's local frame
    d = np.asarray(dirs, dtype=F32)
    if FUSED:
        from tracer import wavefront

        if wavefront.applies(scene, integrator):  # the same numbers, a bounce in compiled passes
            return wavefront.trace(scene, o, np.ascontiguousarray(d), rng, max_depth, rr_depth, threads, out)
    idx = np.arange(n_rays)
    beta = np.ones((n_rays, 3), dtype=F32)
    L = np.zeros((n_rays, 3), dtype=F32)
    prev_pdf = np.zeros(n_rays, dtype=F32)
    specular = np.ones(n_rays, dtype=bool)  # camera ray or after a delta bounce: no MIS on emitters

    depth = 0
    while len(idx):
        prim, t = accel.intersect(o, d, threads=threads)
        hit = np.flatnonzero(prim >= 0)
        if len(hit) < len(idx):
            miss = np.flatnonzero(prim < 0)
            if env is not None:
                dm = take(d, miss)
                if mis:
                    w = np.where(specular[miss], F32(1), power_heuristic(prev_pdf[miss], p_env * env.pdf(dm)))
                else:
                    w = specular[miss].astype(F32)
                L[miss] += take(beta, miss) * env.eval(dm) * w[:, None]
            out[idx[miss]] = take(L, miss)
            idx, o, d, beta, L = idx[hit], take(o, hit), take(d, hit), take(beta, hit), take(L, hit)
            prev_pdf, specular, prim, t = prev_pdf[hit], specular[hit], prim[hit], t[hit]
            if not len(idx):
                break
        p = o + t[:, None] * d
        wo = -d
        ng = take(scene.normals, prim)
        cos_o = dot(ng, wo)
        front = cos_o > 0
        n = ng * np.where(front, F32(1), F32(-1))[:, None]
        mat = scene.material_ids[prim]

        # emission reached by the previous bounce (or seen directly)
        em = scene.emissive[prim]
        if em.any():
            e = np.flatnonzero(em & (front | table.two_sided[mat]))
            if len(e):
                if mis:
                    light_pdf = p_area * scene.light_area_pdf[prim[e]] * t[e] ** 2 / np.maximum(np.abs(cos_o[e]), 1e-12)
                    w = np.where(specular[e], F32(1), power_heuristic(prev_pdf[e], light_pdf))
                else:
                    w = specular[e].astype(F32)
                L[e] += take(beta, e) * take(table.emission, mat[e]) * w[:, None]
        if depth >= max_depth:
            break

        # next-event estimation at non-specular vertices
        if has_mirror:
            nee = np.flatnonzero(table.kind[mat] != MIRROR)
            if len(nee):
                L[nee] += _next_event(scene, take(p, nee), take(n, nee), take(wo, nee), mat[nee], take(beta, nee),
                                      rng, p_area, p_env, mis, eps, threads)
        else:
            L += _next_event(scene, p, n, wo, mat, beta, rng, p_area, p_env, mis, eps, threads)

        if not mis:  # direct lighting: only specular bounces continue
            keep = np.flatnonzero(table.kind[mat] == MIRROR) if has_mirror else np.zeros(0, dtype=np.int64)
            if len(keep) < len(idx):
                done = np.setdiff1d(np.arange(len(idx)), keep, assume_unique=True)
                out[idx[done]] = take(L, done)
            if not len(keep):
                return out
            idx, p, n, wo, mat, beta, L = (idx[keep], take(p, keep), take(n, keep), take(wo, keep), mat[keep],
                                           take(beta, keep), take(L, keep))
        # continue the path by sampling the BSDF
        wi, weight, pdf, delta = table.sample(mat, n, wo, rng.random((len(idx), 3), dtype=F32))
        beta *= weight
        depth += 1
        bmax = np.maximum(np.maximum(beta[:, 0], beta[:, 1]), beta[:, 2])
        if depth >= rr_depth:
            q = np.minimum(bmax, F32(1))
            survive = rng.random(len(idx), dtype=F32) < q
            beta /= np.where(survive, q, F32(1))[:, None]
            alive = survive & (bmax > 0)
        else:
            alive = bmax > 0
        o = p + eps * n  # the next ray leaves from just above the surface
        live = np.flatnonzero(alive)
        if len(live) < len(idx):
            dead = np.flatnonzero(~alive)
            out[idx[dead]] = take(L, dead)
            idx, o, wi, beta, L = idx[live], take(o, live), take(wi, live), take(beta, live), take(L, live)
            pdf, delta = pdf[live], delta[live]
        d = wi
        prev_pdf = pdf
        specular = delta
    if len(idx):
        out[idx] = L
    return out


def _next_event(scene, p, n, wo, mat, beta, rng, p_area, p_env, mis, eps, threads) -> np.ndarray:
    """Light-sampled direct lighting at surface points ``p`` (all non-specular), times ``beta``."""
    table = scene.table
    m = len(p)
    origin = p + eps * n
    contrib = np.zeros((m, 3), dtype=F32)
    # one light strategy per point: area lights or the environment
    u = rng.random((m, 4), dtype=F32)
    if scene.has_area_lights and p_area >= 1 and table.lambertian_only and FUSED:
        from tracer.kernels import area_light_samples  # the same numbers, in one compiled pass

        src, wig, reach, val = area_light_samples(scene, p, n, mat, u, p_area, mis, eps)
        if len(src):
            vis = np.flatnonzero(~scene.accel.occluded(take(origin, src), wig, reach, threads=threads))
            contrib[src[vis]] = take(val, vis)
    elif scene.has_area_lights:
        a = np.flatnonzero(u[:, 3] < p_area) if p_area < 1 else None
        ua, pa, na = (u, p, n) if a is None else (take(u, a), take(p, a), take(n, a))
        k = scene.light_triangles[scene.light_dist.sample_discrete(ua[:, 0])]
        b1, b2 = uniform_triangle(ua[:, 1], ua[:, 2])
        wi = take(scene.v0, k) + b1[:, None] * take(scene.e1, k) + b2[:, None] * take(scene.e2, k) - pa
        dist2 = dot(wi, wi)
        dist = np.sqrt(dist2)
        wi /= dist[:, None]
        cos_l = -dot(take(scene.normals, k), wi)
        lmat = scene.material_ids[k]
        cos_i = dot(na, wi)
        g = np.flatnonzero((cos_i > 0) & ((cos_l > 0) | table.two_sided[lmat]))
        if len(g):
            src = g if a is None else a[g]
            light_pdf = p_area * scene.light_area_pdf[k[g]] * dist2[g] / np.maximum(np.abs(cos_l[g]), 1e-12)
            wig = take(wi, g)
            fcos, bsdf_pdf = table.eval(mat[src], n, wo, wig, cos_i[g], rows=src)
            w = power_heuristic(light_pdf, bsdf_pdf) if mis else F32(1)
            val = fcos * take(table.emission, lmat[g]) * (w / light_pdf)[:, None]
            blocked = scene.accel.occluded(take(origin, src), wig, dist[g] * F32(1 - 1e-4) - 2 * eps, threads=threads)
            vis = np.flatnonzero(~blocked)
            contrib[src[vis]] = take(val, vis)
    env = scene.environment
    if env is not None and p_env > 0:
        e = np.flatnonzero(u[:, 3] >= p_area) if p_area > 0 else np.arange(m)
        if len(e):
            wi, env_pdf = env.sample(take(u, e)[:, :2])
            cos_i = dot(take(n, e), wi)
            g = np.flatnonzero((cos_i > 0) & (env_pdf > 0))
            if len(g):
                eg, wig = e[g], take(wi, g)
                light_pdf = p_env * env_pdf[g]
                fcos, bsdf_pdf = table.eval(mat[eg], n, wo, wig, cos_i[g], rows=eg)
                w = power_heuristic(light_pdf, bsdf_pdf) if mis else F32(1)
                blocked = scene.accel.occluded(take(origin, eg), wig, None, threads=threads)
                vis = np.flatnonzero(~blocked)
                contrib[eg[vis]] += take(fcos, vis) * env.eval(take(wig, vis)) * (w / light_pdf)[vis, None]
    for pos, inten in zip(scene.point_light_pos, scene.point_light_int):
        wi = pos[None, :] - p
        dist2 = dot(wi, wi)
        dist = np.sqrt(dist2)
        wi /= dist[:, None]
        cos_i = dot(n, wi)
        g = np.flatnonzero(cos_i > 0)
        if len(g):
            wig = take(wi, g)
            fcos, _ = table.eval(mat[g], n, wo, wig, cos_i[g], rows=g)
            blocked = scene.accel.occluded(take(origin, g), wig, dist[g] * F32(1 - 1e-4) - 2 * eps, threads=threads)
            vis = np.flatnonzero(~blocked)
            contrib[g[vis]] += take(fcos, vis) * inten[None, :] / dist2[g[vis]][:, None]
    contrib *= beta
    return contrib
