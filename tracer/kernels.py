"""Compiled (numba) light sampling for the NumPy integrator, where it dominates a render's time.

``area_light_samples``: next-event estimation to the area lights at Lambertian points (pick a light
triangle by power, a uniform point on it, the geometry terms, the BSDF, the MIS weight); the shadow rays
are left to the caller. It does per point what :mod:`tracer.integrators` does with whole-array NumPy
steps, in the same float32 operations in the same order, so the image is the same bit for bit
(``tracer.integrators.FUSED`` switches it off; tests compare both ways). Compiled on first use, cached on
disk, it releases the GIL, so the bands of a render run it on several threads at once.

The whole bounce loop of Lambertian scenes lit by area lights (:mod:`tracer.wavefront`) is C++
(``src/native/tracer_paths.cpp``), with its own copy of ``_light_sample``: a render of those scenes does
not load numba at all (its import and first call cost about half a second per process).
"""

from __future__ import annotations

import numba
import numpy as np

F32 = np.float32
zero, one, tiny, inv_pi = F32(0), F32(1), F32(1e-12), F32(1.0 / np.pi)
shrink = F32(1 - 1e-4)


@numba.njit(cache=True, nogil=True, inline="always")
def _light_sample(u, p0, p1, p2, n0, n1, n2, cdf, light_tris, v0, e1, e2, normals, material_ids, two_sided,
                 light_area_pdf, p_area, mis):  # pragma: no cover - compiled
    """A point on an area light seen from ``p``: (ok, light material, direction, distance, weight / pdf,
    cos_i) in the order of the NumPy steps."""
    x = np.float64(u[0])
    nbins = cdf.shape[0] - 1
    lo, hi = 0, nbins + 1  # np.searchsorted(cdf, x, side="right"), by bisection
    while lo < hi:
        mid = (lo + hi) >> 1
        if cdf[mid] <= x:
            lo = mid + 1
        else:
            hi = mid
    j = min(max(lo - 1, 0), nbins - 1)
    k = light_tris[j]
    su = np.sqrt(u[1])
    b1 = one - su
    b2 = u[2] * su
    w0 = v0[k, 0] + b1 * e1[k, 0] + b2 * e2[k, 0] - p0
    w1 = v0[k, 1] + b1 * e1[k, 1] + b2 * e2[k, 1] - p1
    w2 = v0[k, 2] + b1 * e1[k, 2] + b2 * e2[k, 2] - p2
    dist2 = w0 * w0 + w1 * w1 + w2 * w2
    dist = np.sqrt(dist2)
    w0 /= dist
    w1 /= dist
    w2 /= dist
    cos_l = -(normals[k, 0] * w0 + normals[k, 1] * w1 + normals[k, 2] * w2)
    lmat = material_ids[k]
    cos_i = n0 * w0 + n1 * w1 + n2 * w2
    if not (cos_i > 0 and (cos_l > 0 or two_sided[lmat])):
        return False, lmat, w0, w1, w2, dist, zero, zero
    light_pdf = p_area * light_area_pdf[k] * dist2 / max(abs(cos_l), tiny)
    bsdf_pdf = max(cos_i, zero) * inv_pi
    w = one
    if mis:
        a2 = light_pdf * light_pdf
        s = a2 + bsdf_pdf * bsdf_pdf
        w = a2 / s if s > 0 else zero
    return True, lmat, w0, w1, w2, dist, w / light_pdf, bsdf_pdf

@numba.njit(cache=True, nogil=True)
def _area_light_samples(p, n, mat, u, cdf, light_tris, v0, e1, e2, normals, material_ids, two_sided,
                       light_area_pdf, kd, emission, p_area, mis, eps2):  # pragma: no cover - compiled
    m = p.shape[0]
    rows = np.empty(m, np.int64)
    wi_out = np.empty((m, 3), np.float32)
    tmax = np.empty(m, np.float32)
    val = np.empty((m, 3), np.float32)
    g = 0
    for i in range(m):
        ok, lmat, w0, w1, w2, dist, scale, bsdf_pdf = _light_sample(
            u[i], p[i, 0], p[i, 1], p[i, 2], n[i, 0], n[i, 1], n[i, 2], cdf, light_tris, v0, e1, e2, normals,
            material_ids, two_sided, light_area_pdf, p_area, mis)
        if not ok:
            continue
        mt = mat[i]
        for c in range(3):
            val[g, c] = kd[mt, c] * bsdf_pdf * emission[lmat, c] * scale
        rows[g] = i
        wi_out[g, 0] = w0
        wi_out[g, 1] = w1
        wi_out[g, 2] = w2
        tmax[g] = dist * shrink - eps2
        g += 1
    return rows[:g], wi_out[:g], tmax[:g], val[:g]

def area_light_samples(scene, p, n, mat, u, p_area: float, mis: bool, eps):
    """Rows (int64) of the points whose light sample faces both ways, the unit directions to the sampled
    points, the shadow rays' reach and the unshadowed contributions (float32); see the module's note."""
    t = scene.table
    return _area_light_samples(p, n, mat, u, scene.light_dist.cdf, scene.light_triangles, scene.v0, scene.e1, scene.e2,
                        scene.normals, scene.material_ids, t.two_sided, scene.light_area_pdf, t.kd, t.emission,
                        F32(p_area), bool(mis), F32(2 * eps))
