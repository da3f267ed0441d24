"""Image error metrics for comparing a warped (or otherwise approximated) HDR image with a reference.

Every metric is a pure function of two linear-light float images ``H x W x C`` and a boolean mask of
the pixels to compare (``H x W``), and returns plain Python floats. The mask is normally
:func:`valid_mask`: the pixels fully covered in both images (alpha = 1), so that the rim of a fisheye,
the missing tile of a grid or a pixel the warp could not fill never counts as error.

Definitions (``r`` reference, ``t`` test, sums over masked pixels and all colour channels):

- **relative L1** ``sum |t - r| / sum |r|``: the aggregate form, stable where the reference is dark.
- **PSNR of log radiance**: ``10 log10(peak^2 / mean((log(t+e) - log(r+e))^2))`` with ``e`` a floor of
  ``1e-3`` times the mean reference value and ``peak`` the range of ``log(r+e)`` over the mask; it weighs
  an error in a shadow like the same relative error in a highlight.
- **share off by more than 5%**: the fraction of masked pixels whose per-pixel relative error
  ``sum_c |t - r| / max(sum_c r, floor)`` exceeds 0.05 (``floor`` = 1% of the mean pixel sum, so that
  near-black pixels are judged by an absolute error instead of dividing by zero).
- **FLIP** (NVIDIA's perceptual difference, ``flip-evaluator``) on the two images tone-mapped by the
  same curve and exposure and sRGB-encoded, averaged over the mask.
- **Monte Carlo noise floor**: a reference traced with ``n`` samples per pixel carries a per-pixel
  standard error ``sigma = sqrt(var / n)``. Against an exact test image, that noise alone gives an
  expected relative L1 of ``sqrt(2/pi) sum sigma / sum |r|`` (the mean absolute value of a normal
  variable). It is reported next to the measured error so a warp is never blamed for the reference's
  noise; the excess is what the warp itself adds. Monte Carlo noise at a few samples per pixel is
  heavy-tailed, which makes that normal formula pessimistic; rendering the reference as two halves
  with independent seeds gives an estimate free of that assumption (:func:`noise_floor_split`).
- **edge masks**: pixels within ``radius`` pixels of a silhouette or shadow edge, found from
  depth / normal / primitive-id discontinuities when the renderer provides them and from the gradients
  of the (denoised) log luminance of the reference otherwise. Errors are reported on the edges and on
  the rest separately (:func:`compare`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "valid_mask", "relative_l1", "psnr_log", "share_off", "flip", "noise_floor", "noise_floor_split", "rmse",
    "edge_mask_from_aovs", "edge_mask_from_image", "dilate", "error_map", "compare",
]

FULL_COVERAGE = 0.999  # alpha at or above this counts as fully covered (alpha is a sample fraction)


# -- masks ---------------------------------------------------------------------------------------
def _as_image(a, what: str) -> np.ndarray:
    arr = np.asarray(a)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.ndim != 3:
        raise ValueError(f"{what} must be an H x W or H x W x C image, got shape {arr.shape}")
    return arr


def _alpha2d(alpha, shape) -> np.ndarray:
    if alpha is None:
        return np.ones(shape, dtype=bool)
    a = np.asarray(alpha)
    if a.ndim == 3:
        a = a[..., 0]
    if a.shape != tuple(shape):
        raise ValueError(f"alpha has shape {a.shape}, the image is {tuple(shape)}")
    return a


def valid_mask(ref_alpha=None, test_alpha=None, shape=None, threshold: float = FULL_COVERAGE) -> np.ndarray:
    """Pixels fully covered in both images: ``ref_alpha >= threshold`` and ``test_alpha >= threshold``.

    Either alpha may be None (everything covered); ``shape`` (H, W) is needed when both are None.
    Pixels with a non-finite alpha are excluded.
    """
    if shape is None:
        for a in (ref_alpha, test_alpha):
            if a is not None:
                shape = np.asarray(a).shape[:2]
                break
        else:
            raise ValueError("valid_mask needs an alpha or a shape")
    mask = np.ones(tuple(shape), dtype=bool)
    for a in (ref_alpha, test_alpha):
        if a is not None:
            a2 = np.asarray(_alpha2d(a, shape), dtype=np.float64)
            mask &= np.isfinite(a2) & (a2 >= threshold)
    return mask


def _prep(ref, test, mask):
    r = _as_image(ref, "reference").astype(np.float64, copy=False)
    t = _as_image(test, "test").astype(np.float64, copy=False)
    if r.shape != t.shape:
        raise ValueError(f"reference {r.shape} and test {t.shape} differ in shape; warp to the same size")
    m = np.ones(r.shape[:2], dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    if m.shape != r.shape[:2]:
        raise ValueError(f"mask has shape {m.shape}, the images are {r.shape[:2]}")
    m = m & np.all(np.isfinite(r), axis=-1) & np.all(np.isfinite(t), axis=-1)
    return r, t, m


# -- scalar metrics ------------------------------------------------------------------------------
def relative_l1(ref, test, mask=None) -> float:
    """Aggregate relative L1 ``sum |t - r| / sum |r|`` over masked pixels and all channels.

    Returns NaN when the mask is empty, 0 when both images are 0 there, inf when only the reference is.
    """
    r, t, m = _prep(ref, test, mask)
    if not m.any():
        return float("nan")
    num = float(np.abs(t[m] - r[m]).sum())
    den = float(np.abs(r[m]).sum())
    if den == 0.0:
        return 0.0 if num == 0.0 else float("inf")
    return num / den


def rmse(ref, test, mask=None) -> float:
    """Root mean squared difference over masked pixels and channels (linear radiance units)."""
    r, t, m = _prep(ref, test, mask)
    if not m.any():
        return float("nan")
    return float(np.sqrt(np.mean((t[m] - r[m]) ** 2)))


def psnr_log(ref, test, mask=None, floor: float = 1e-3) -> float:
    """PSNR (dB) of log radiance; see the module docstring. inf for identical images."""
    r, t, m = _prep(ref, test, mask)
    if not m.any():
        return float("nan")
    rv, tv = np.maximum(r[m], 0.0), np.maximum(t[m], 0.0)
    eps = floor * float(rv.mean()) if rv.mean() > 0 else floor
    lr, lt = np.log(rv + eps), np.log(tv + eps)
    mse = float(np.mean((lt - lr) ** 2))
    peak = float(lr.max() - lr.min())
    if mse == 0.0:
        return float("inf")
    if peak == 0.0:
        peak = 1.0  # a flat reference: judge against one e-fold
    return 10.0 * math.log10(peak * peak / mse)


def pixel_relative_error(ref, test, floor_fraction: float = 0.01) -> np.ndarray:
    """Per-pixel relative error ``sum_c |t - r| / max(sum_c |r|, floor)``, float64 ``H x W``.

    ``floor`` is ``floor_fraction`` times the mean of ``sum_c |r|`` over the image (finite pixels).
    """
    r = _as_image(ref, "reference").astype(np.float64, copy=False)
    t = _as_image(test, "test").astype(np.float64, copy=False)
    num = np.abs(t - r).sum(axis=-1)
    den = np.abs(r).sum(axis=-1)
    finite = np.isfinite(den)
    mean = float(den[finite].mean()) if finite.any() else 0.0
    floor = floor_fraction * mean if mean > 0 else 1e-12
    with np.errstate(invalid="ignore"):
        return num / np.maximum(den, floor)


def share_off(ref, test, mask=None, tolerance: float = 0.05, floor_fraction: float = 0.01) -> float:
    """Fraction of masked pixels whose relative error exceeds ``tolerance`` (5% by default)."""
    r, t, m = _prep(ref, test, mask)
    if not m.any():
        return float("nan")
    e = pixel_relative_error(r, t, floor_fraction)
    return float(np.mean(e[m] > tolerance))


def error_map(ref, test, mask=None, floor_fraction: float = 0.01) -> np.ndarray:
    """Per-pixel relative error for display (float32 ``H x W``); NaN outside the mask."""
    r, t, m = _prep(ref, test, mask)
    e = pixel_relative_error(r, t, floor_fraction)
    return np.where(m, e, np.nan).astype(np.float32)


def _display(image: np.ndarray, curve: str, exposure: float) -> np.ndarray:
    """Tone-map (lenslab.tone) then sRGB-encode (colour-science) to 3-channel float32 in [0, 1]."""
    import warnings

    from lenslab.io.encode import encode_srgb
    from lenslab.tone import tonemap

    img = _as_image(image, "image").astype(np.float32, copy=False)
    if img.shape[-1] == 1:
        img = np.repeat(img, 3, axis=-1)
    elif img.shape[-1] == 4:
        img = img[..., :3]
    img = np.where(np.isfinite(img), np.maximum(img, 0.0), 0.0).astype(np.float32)
    with warnings.catch_warnings():  # values are cleaned above; nothing for the curve to report
        warnings.simplefilter("ignore")
        disp = np.asarray(tonemap(img, curve=curve, exposure=exposure), dtype=np.float32)
    return np.ascontiguousarray(encode_srgb(disp), dtype=np.float32)


def flip(ref, test, mask=None, curve: str = "hable", exposure: float = 0.0, return_map: bool = False,
         ppd: float | None = None):
    """Mean LDR-FLIP error over the mask of the two images tone-mapped alike (0 = identical, 1 = worst).

    Both images go through :func:`lenslab.tone.tonemap` with the same ``curve`` and ``exposure`` and the
    sRGB encoding, then ``flip_evaluator.evaluate(..., "LDR")``; the per-pixel map is averaged over the
    mask (FLIP itself sees the whole image, since its filters span neighbouring pixels). With
    ``return_map=True`` returns ``(mean, map)``, the map float32 ``H x W``.
    """
    import flip_evaluator

    r, t, m = _prep(ref, test, mask)
    params = {} if ppd is None else {"ppd": float(ppd)}
    rd = np.where(m[..., None], _display(r, curve, exposure), 0.0).astype(np.float32)
    td = np.where(m[..., None], _display(t, curve, exposure), 0.0).astype(np.float32)
    fmap, _, _ = flip_evaluator.evaluate(rd, td, "LDR", inputsRGB=True, applyMagma=False,
                                         computeMeanError=False, parameters=params)
    fmap = np.asarray(fmap, dtype=np.float32).reshape(r.shape[:2])
    mean = float(fmap[m].mean()) if m.any() else float("nan")
    return (mean, fmap) if return_map else mean


def noise_floor(ref, ref_stderr, mask=None) -> dict[str, float]:
    """What the reference's own Monte Carlo noise alone contributes to the metrics.

    ``ref_stderr`` is the per-pixel, per-channel standard error of the reference's mean (same shape as
    the reference, or ``H x W`` for all channels); for a renderer reporting the sample variance ``var``
    of ``n`` samples per pixel pass ``sqrt(var / n)``.

    Returns ``l1`` (expected relative L1 of the noise against an exact image: ``sqrt(2/pi) sum sigma /
    sum |r|``), ``rmse`` (``sqrt(mean sigma^2)``) and ``relative_stderr`` (``sqrt(sum sigma^2) / sum |r|``,
    the standard error of the image mean, relative).
    """
    r = _as_image(ref, "reference").astype(np.float64, copy=False)
    s = _as_image(ref_stderr, "reference standard error").astype(np.float64, copy=False)
    s = np.broadcast_to(s, r.shape)
    m = np.ones(r.shape[:2], dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    m = m & np.all(np.isfinite(r), axis=-1) & np.all(np.isfinite(s), axis=-1)
    if not m.any():
        return {"l1": float("nan"), "rmse": float("nan"), "relative_stderr": float("nan")}
    den = float(np.abs(r[m]).sum())
    sig = np.abs(s[m])
    if den == 0.0:
        return {"l1": float("nan"), "rmse": float(np.sqrt(np.mean(sig ** 2))), "relative_stderr": float("nan")}
    return {
        "l1": math.sqrt(2.0 / math.pi) * float(sig.sum()) / den,
        "rmse": float(np.sqrt(np.mean(sig ** 2))),
        "relative_stderr": float(np.sqrt(np.sum(sig ** 2))) / den,
    }


def noise_floor_split(half_a, half_b, mask=None) -> float:
    """Expected relative L1 of the noise of ``(half_a + half_b) / 2`` against the exact image.

    ``half_a`` and ``half_b`` are two independent renders with half the samples each (different seeds).
    Their difference ``(n_a - n_b)/2`` has the distribution of the noise of their mean when the noise is
    symmetric, whatever its shape, so ``sum |a - b| / 2 / sum |(a + b)/2|`` estimates the noise L1
    without assuming normality. (Monte Carlo noise at a few samples per pixel is heavy-tailed: there
    the normal formula of :func:`noise_floor` overestimates the L1, by about 2x at 16 spp.)
    """
    a, b, m = _prep(half_a, half_b, mask)
    if not m.any():
        return float("nan")
    den = float(np.abs(0.5 * (a[m] + b[m])).sum())
    if den == 0.0:
        return float("nan")
    return 0.5 * float(np.abs(a[m] - b[m]).sum()) / den


# -- edges ---------------------------------------------------------------------------------------
def _disk(radius: int) -> np.ndarray:
    k = 2 * int(radius) + 1
    yy, xx = np.mgrid[-radius:radius + 1, -radius:radius + 1]
    return ((xx * xx + yy * yy) <= radius * radius + 0.5).astype(np.uint8).reshape(k, k)


def dilate(mask, radius: int = 2) -> np.ndarray:
    """Boolean dilation by a disk of ``radius`` pixels (cv2.dilate)."""
    import cv2

    m = np.asarray(mask, dtype=bool)
    if radius <= 0:
        return m.copy()
    return cv2.dilate(m.astype(np.uint8), _disk(int(radius)), borderType=cv2.BORDER_CONSTANT,
                      borderValue=0).astype(bool)


def _neighbour_diff(a: np.ndarray, fn) -> np.ndarray:
    """Mark both pixels of every horizontally or vertically adjacent pair where ``fn(p, q)`` is True."""
    out = np.zeros(a.shape[:2], dtype=bool)
    h = fn(a[:, :-1], a[:, 1:])
    out[:, :-1] |= h
    out[:, 1:] |= h
    v = fn(a[:-1, :], a[1:, :])
    out[:-1, :] |= v
    out[1:, :] |= v
    return out


def edge_mask_from_aovs(depth=None, normal=None, prim_id=None, radius: int = 2,
                        depth_tolerance: float = 0.02, normal_tolerance_deg: float = 20.0) -> np.ndarray:
    """Pixels within ``radius`` px of a geometric discontinuity, from the renderer's AOVs.

    - ``prim_id`` (``H x W`` ints, -1 = miss): edges where neighbours see different objects/primitives.
    - ``depth`` (``H x W``, inf or 0 = miss): relative depth jumps above ``depth_tolerance`` (silhouettes).
    - ``normal`` (``H x W x 3``): normals turning by more than ``normal_tolerance_deg`` (creases).
    Give at least one. Shadow edges are not geometric: combine with :func:`edge_mask_from_image`.
    """
    if depth is None and normal is None and prim_id is None:
        raise ValueError("edge_mask_from_aovs needs depth, normal or prim_id")
    edges = None
    if prim_id is not None:
        pid = np.asarray(prim_id)
        pid = pid[..., 0] if pid.ndim == 3 else pid
        e = _neighbour_diff(pid, lambda p, q: p != q)
        edges = e if edges is None else edges | e
    if depth is not None:
        d = np.asarray(depth, dtype=np.float64)
        d = d[..., 0] if d.ndim == 3 else d
        hit = np.isfinite(d) & (d > 0)
        dd = np.where(hit, d, 0.0)

        def jump(p, q):
            ph, qh = p > 0, q > 0
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.abs(p - q) / np.maximum(np.minimum(p, q), 1e-12)
            return (ph != qh) | (ph & qh & (rel > depth_tolerance))

        e = _neighbour_diff(dd, jump)
        edges = e if edges is None else edges | e
    if normal is not None:
        n = np.asarray(normal, dtype=np.float64)
        cos_tol = math.cos(math.radians(normal_tolerance_deg))
        e = _neighbour_diff(n, lambda p, q: np.einsum("...i,...i->...", p, q) < cos_tol * (
            np.linalg.norm(p, axis=-1) * np.linalg.norm(q, axis=-1)))
        edges = e if edges is None else edges | e
    return dilate(edges, radius)


def edge_mask_from_image(image, radius: int = 2, threshold: float = 0.25, denoise: bool = True,
                         mask=None) -> np.ndarray:
    """Pixels within ``radius`` px of a strong edge of the image's log luminance.

    The log luminance (Rec.709 weights, floored at 1e-3 of its mean) is denoised with an edge-preserving
    bilateral filter when ``denoise`` is set (Monte Carlo noise would otherwise read as edges), then an
    edge is a pixel whose central-difference gradient magnitude exceeds ``threshold`` (in natural-log
    units per pixel: 0.25 is a 28% step between neighbours). Pixels outside ``mask`` (e.g. alpha < 1)
    and their boundary count as edges, since the rim of a lens is a silhouette too.
    """
    import cv2

    img = _as_image(image, "image").astype(np.float64, copy=False)
    if img.shape[-1] >= 3:
        lum = img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722
    else:
        lum = img[..., 0]
    lum = np.where(np.isfinite(lum), np.maximum(lum, 0.0), 0.0)
    mean = float(lum.mean()) if lum.size else 0.0
    eps = 1e-3 * mean if mean > 0 else 1e-6
    log = np.log(lum + eps).astype(np.float32)
    if denoise:
        log = cv2.bilateralFilter(log, d=5, sigmaColor=0.3, sigmaSpace=1.5)
    gy, gx = np.gradient(log.astype(np.float64))
    edges = np.hypot(gx, gy) > threshold
    if mask is not None:
        m = np.asarray(mask, dtype=bool)
        edges |= ~m
    return dilate(edges, radius)


# -- everything at once --------------------------------------------------------------------------
def compare(ref, test, ref_alpha=None, test_alpha=None, mask=None, edges=None, ref_stderr=None,
            with_flip: bool = True, tone_curve: str = "hable", exposure: float = 0.0,
            ref_halves=None) -> dict[str, Any]:
    """All metrics of ``test`` against ``ref``: overall, on the edges and away from them.

    ``mask`` defaults to :func:`valid_mask` of the two alphas. ``edges`` is a boolean ``H x W`` mask
    (see the edge functions); without it only the overall figures are given. ``ref_stderr`` adds the
    reference's noise floor (overall and per region) and ``excess_l1``, the measured relative L1 minus
    the noise floor (never negative; a lower bound of the error the test itself adds). With
    ``ref_halves=(a, b)``, the reference being the mean of two independent half-sample renders, the
    floor is the empirical :func:`noise_floor_split` instead (the normal formula is then reported as
    ``noise_l1_normal``).

    Returns a flat dict of floats: ``l1``, ``psnr_log``, ``off5``, ``rmse``, ``flip``, ``pixels``, and
    the same with ``_edge`` / ``_interior`` suffixes, plus ``noise_l1*`` and ``excess_l1*``.
    """
    r = _as_image(ref, "reference")
    if mask is None:
        mask = valid_mask(ref_alpha, test_alpha, shape=r.shape[:2])
    mask = np.asarray(mask, dtype=bool)
    regions = {"": mask}
    if edges is not None:
        e = np.asarray(edges, dtype=bool)
        regions["_edge"] = mask & e
        regions["_interior"] = mask & ~e
    out: dict[str, Any] = {}
    for suffix, m in regions.items():
        out["pixels" + suffix] = int(m.sum())
        out["l1" + suffix] = relative_l1(r, test, m)
        out["psnr_log" + suffix] = psnr_log(r, test, m)
        out["off5" + suffix] = share_off(r, test, m)
        out["rmse" + suffix] = rmse(r, test, m)
        floor = None
        if ref_stderr is not None:
            floor = noise_floor(r, ref_stderr, m)["l1"]
        if ref_halves is not None:
            if floor is not None:
                out["noise_l1_normal" + suffix] = floor
            floor = noise_floor_split(ref_halves[0], ref_halves[1], m)
        if floor is not None:
            out["noise_l1" + suffix] = floor
            out["excess_l1" + suffix] = max(out["l1" + suffix] - floor, 0.0) if np.isfinite(floor) \
                else out["l1" + suffix]
    if with_flip:
        mean, fmap = flip(r, test, mask, curve=tone_curve, exposure=exposure, return_map=True)
        out["flip"] = mean
        if edges is not None:
            for suffix in ("_edge", "_interior"):
                m = regions[suffix]
                out["flip" + suffix] = float(fmap[m].mean()) if m.any() else float("nan")
    return out
