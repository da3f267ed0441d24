"""Compiled (numba) steps of the integrators, for the cases that dominate a render's time.

Each kernel does per point what :mod:`tracer.integrators` does with whole-array NumPy steps, in the same
float32 operations in the same order, so the image is the same bit for bit (``tracer.integrators.FUSED``
switches them off; tests compare both ways). Ray casts stay with embree. Kernels are compiled on first
use, cached on disk, and release the GIL, so the bands of a render run them on several threads at once.

- ``area_light_samples``: next-event estimation to the area lights at Lambertian points (pick a light
  triangle by power, a uniform point on it, the geometry terms, the BSDF, the MIS weight); the shadow
  rays are left to the caller.
- ``shade`` and ``settle``: one whole bounce of the path tracer in Lambertian scenes lit by area lights
  (:mod:`tracer.wavefront`): the emission the ray reached with its MIS weight, the light sample and its
  shadow ray, the cosine-weighted continuation and Russian roulette (``shade``); then, once embree has
  answered the shadow rays, the visible light added and the finished paths written out (``settle``).
  The cosine and sine of the sampled azimuths come in from NumPy, so that they are NumPy's own values.
"""

from __future__ import annotations

import numba
import numpy as np

from tracer.embree_api import INVALID, RAYHIT_WORDS, externals

F32 = np.float32
_rtc_intersect, _rtc_occluded, _as_pointer = externals()
zero, one, two, tiny, inv_pi = F32(0), F32(1), F32(2), F32(1e-12), F32(1.0 / np.pi)
shrink, short = F32(1 - 1e-4), F32(1e-6)
far = F32(1e37)  # the reach of an unbounded ray, as embreex gives it


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

@numba.njit(cache=True, nogil=True)
def _shade(prim, t, o, d, beta, L, prev_pdf, specular, idx, out, normals, material_ids, emissive, two_sided,
           light_area_pdf, emission, kd, cdf, light_tris, v0, e1, e2, u_nee, u_bsdf, cphi, sphi, u_rr, p_area, eps,
           eps2, last, rr, alive, sh_rows, sh_o, sh_d, sh_t, sh_val):  # pragma: no cover - compiled
    """One bounce, in place: path ``i`` of the live paths moves to row ``j <= i`` (the ``j``-th that hit), so
    the state needs no second copy; the shadow rays go to the ``sh_`` rows. Returns the counts of both."""
    j = 0
    g = 0
    for i in range(prim.shape[0]):
        k = prim[i]
        r = idx[i]
        if k < 0:  # a miss: no environment in these scenes, the path ends
            for c in range(3):
                out[r, c] = L[i, c]
            continue
        ti = t[i]
        dx, dy, dz = d[i, 0], d[i, 1], d[i, 2]
        p0, p1, p2 = o[i, 0] + ti * dx, o[i, 1] + ti * dy, o[i, 2] + ti * dz
        cos_o = normals[k, 0] * -dx + normals[k, 1] * -dy + normals[k, 2] * -dz
        front = cos_o > 0
        sign = one if front else -one
        n0, n1, n2 = normals[k, 0] * sign, normals[k, 1] * sign, normals[k, 2] * sign
        mt = material_ids[k]
        l0, l1, l2 = L[i, 0], L[i, 1], L[i, 2]
        b0, b1, b2 = beta[i, 0], beta[i, 1], beta[i, 2]
        if emissive[k] and (front or two_sided[mt]):
            w = one
            if not specular[i]:
                light_pdf = p_area * light_area_pdf[k] * (ti * ti) / max(abs(cos_o), tiny)
                a2 = prev_pdf[i] * prev_pdf[i]
                s = a2 + light_pdf * light_pdf
                w = a2 / s if s > 0 else zero
            l0 += b0 * emission[mt, 0] * w
            l1 += b1 * emission[mt, 1] * w
            l2 += b2 * emission[mt, 2] * w
        if last:
            out[r, 0], out[r, 1], out[r, 2] = l0, l1, l2
            continue
        idx[j] = r
        L[j, 0], L[j, 1], L[j, 2] = l0, l1, l2
        q0, q1, q2 = p0 + eps * n0, p1 + eps * n1, p2 + eps * n2  # just above the surface
        ok, lmat, w0, w1, w2, dist, scale, bsdf_pdf = _light_sample(
            u_nee[j], p0, p1, p2, n0, n1, n2, cdf, light_tris, v0, e1, e2, normals, material_ids, two_sided,
            light_area_pdf, p_area, True)
        if ok:
            sh_rows[g] = j
            sh_o[g, 0], sh_o[g, 1], sh_o[g, 2] = q0, q1, q2
            sh_d[g, 0], sh_d[g, 1], sh_d[g, 2] = w0, w1, w2
            sh_t[g] = dist * shrink - eps2
            sh_val[g, 0] = kd[mt, 0] * bsdf_pdf * emission[lmat, 0] * scale * b0
            sh_val[g, 1] = kd[mt, 1] * bsdf_pdf * emission[lmat, 1] * scale * b1
            sh_val[g, 2] = kd[mt, 2] * bsdf_pdf * emission[lmat, 2] * scale * b2
            g += 1
        # cosine-weighted continuation: a uniform point on the unit sphere at the tip of n
        z = one - two * u_bsdf[j, 1]
        rad = np.sqrt(max(zero, one - z * z))
        x0, x1, x2 = n0 + rad * cphi[j], n1 + rad * sphi[j], n2 + z
        length = np.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
        if length < short:
            x0, x1, x2 = n0, n1, n2
        else:
            x0, x1, x2 = x0 / length, x1 / length, x2 / length
        d[j, 0], d[j, 1], d[j, 2] = x0, x1, x2
        prev_pdf[j] = (n0 * x0 + n1 * x1 + n2 * x2) * inv_pi
        b0, b1, b2 = b0 * kd[mt, 0], b1 * kd[mt, 1], b2 * kd[mt, 2]  # f cos / pdf = kd
        bmax = max(max(b0, b1), b2)
        if rr:
            q = min(bmax, one)
            survive = u_rr[j] < q
            if survive:
                b0, b1, b2 = b0 / q, b1 / q, b2 / q
            alive[j] = survive and bmax > 0
        else:
            alive[j] = bmax > 0
        beta[j, 0], beta[j, 1], beta[j, 2] = b0, b1, b2
        o[j, 0], o[j, 1], o[j, 2] = q0, q1, q2
        j += 1
    return j, g


@numba.njit(cache=True, nogil=True)
def _ray_buffer():  # pragma: no cover - compiled
    """One ``RTCRayHit``, 16-byte aligned, as float32 words (see tracer.embree_api)."""
    buf = np.empty(RAYHIT_WORDS + 4, np.float32)
    off = ((16 - buf.ctypes.data % 16) % 16) // 4
    return buf[off:off + RAYHIT_WORDS]


@numba.njit(cache=True, nogil=True, inline="always")
def _set_ray(ray, words, o0, o1, o2, d0, d1, d2, tfar):  # pragma: no cover - compiled
    ray[0], ray[1], ray[2], ray[3] = o0, o1, o2, zero
    ray[4], ray[5], ray[6], ray[7] = d0, d1, d2, zero
    ray[8] = tfar
    words[9], words[10], words[11] = INVALID, 0, 0
    words[17], words[18], words[19] = INVALID, INVALID, INVALID


@numba.njit(cache=True, nogil=True)
def _intersect(scene, o, d, n, prim, t):  # pragma: no cover - compiled
    """Closest hits of rays ``0..n``: triangle (-1 for none) and distance (inf for none), as
    :meth:`tracer.accel.Accelerator.intersect` gives them."""
    ray = _ray_buffer()
    words = ray.view(np.uint32)
    sp, rp, null = _as_pointer(scene), _as_pointer(ray.ctypes.data), _as_pointer(0)
    for i in range(n):
        _set_ray(ray, words, o[i, 0], o[i, 1], o[i, 2], d[i, 0], d[i, 1], d[i, 2], far)
        _rtc_intersect(sp, rp, null)
        if words[18] == INVALID:
            prim[i] = -1
            t[i] = np.inf
        else:
            prim[i] = np.int32(words[17])
            t[i] = ray[8]


@numba.njit(cache=True, nogil=True)
def _settle(scene, m, idx, o, d, beta, L, pdf, alive, g, sh_rows, sh_o, sh_d, sh_t, sh_val,
            out):  # pragma: no cover - compiled
    """The shadow rays cast, the visible light samples added, finished paths written to ``out`` and the rest
    moved up; their count."""
    ray = _ray_buffer()
    words = ray.view(np.uint32)
    sp, rp, null = _as_pointer(scene), _as_pointer(ray.ctypes.data), _as_pointer(0)
    for s in range(g):
        _set_ray(ray, words, sh_o[s, 0], sh_o[s, 1], sh_o[s, 2], sh_d[s, 0], sh_d[s, 1], sh_d[s, 2],
                 min(sh_t[s], far))
        _rtc_occluded(sp, rp, null)
        if not ray[8] < 0:  # embree marks a blocked ray with tfar = -inf
            r = sh_rows[s]
            for c in range(3):
                L[r, c] += sh_val[s, c]
    k = 0
    for j in range(m):
        if alive[j]:
            if k != j:
                idx[k] = idx[j]
                pdf[k] = pdf[j]
                for c in range(3):
                    o[k, c], d[k, c], beta[k, c], L[k, c] = o[j, c], d[j, c], beta[j, c], L[j, c]
            k += 1
        else:
            for c in range(3):
                out[idx[j], c] = L[j, c]
    return k


def kernels():
    """The compiled kernels ``(area_light_samples, shade, settle, intersect)`` (compiled or loaded on their
    first call)."""
    return _area_light_samples, _shade, _settle, _intersect


def area_light_samples(scene, p, n, mat, u, p_area: float, mis: bool, eps):
    """Rows (int64) of the points whose light sample faces both ways, the unit directions to the sampled
    points, the shadow rays' reach and the unshadowed contributions (float32); see the module's note."""
    t = scene.table
    return kernels()[0](p, n, mat, u, scene.light_dist.cdf, scene.light_triangles, scene.v0, scene.e1, scene.e2,
                        scene.normals, scene.material_ids, t.two_sided, scene.light_area_pdf, t.kd, t.emission,
                        F32(p_area), bool(mis), F32(2 * eps))
