"""Masks of the pixels to compare, and the scalar error measures of a test image against a reference
(relative L1, RMSE, PSNR of log radiance, the share off by more than 5%, FLIP); see :mod:`lenslab.metrics`."""

from __future__ import annotations

import math

import numpy as np

FULL_COVERAGE = 0.999  # alpha at or above this counts as fully covered (alpha is a sample fraction)


# -- masks ---------------------------------------------------------------------------------------
def as_image(a, what: str) -> np.ndarray:
    from lenslab.errors import check_image_shape

    arr = check_image_shape(a, what, channels=None)
    return arr[..., None] if arr.ndim == 2 else arr


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


def paired_images(ref, test, mask):
    r = as_image(ref, "reference").astype(np.float64, copy=False)
    t = as_image(test, "test").astype(np.float64, copy=False)
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
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    num = float(np.abs(t[m] - r[m]).sum())
    den = float(np.abs(r[m]).sum())
    if den == 0.0:
        return 0.0 if num == 0.0 else float("inf")
    return num / den


def rmse(ref, test, mask=None) -> float:
    """Root mean squared difference over masked pixels and channels (linear radiance units)."""
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    return float(np.sqrt(np.mean((t[m] - r[m]) ** 2)))


def psnr_log(ref, test, mask=None, floor: float = 1e-3) -> float:
    """PSNR (dB) of log radiance; see the module docstring. inf for identical images."""
    r, t, m = paired_images(ref, test, mask)
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
    r = as_image(ref, "reference").astype(np.float64, copy=False)
    t = as_image(test, "test").astype(np.float64, copy=False)
    num = np.abs(t - r).sum(axis=-1)
    den = np.abs(r).sum(axis=-1)
    finite = np.isfinite(den)
    mean = float(den[finite].mean()) if finite.any() else 0.0
    floor = floor_fraction * mean if mean > 0 else 1e-12
    with np.errstate(invalid="ignore"):
        return num / np.maximum(den, floor)


def share_off(ref, test, mask=None, tolerance: float = 0.05, floor_fraction: float = 0.01) -> float:
    """Fraction of masked pixels whose relative error exceeds ``tolerance`` (5% by default)."""
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    e = pixel_relative_error(r, t, floor_fraction)
    return float(np.mean(e[m] > tolerance))


def error_map(ref, test, mask=None, floor_fraction: float = 0.01) -> np.ndarray:
    """Per-pixel relative error for display (float32 ``H x W``); NaN outside the mask."""
    r, t, m = paired_images(ref, test, mask)
    e = pixel_relative_error(r, t, floor_fraction)
    return np.where(m, e, np.nan).astype(np.float32)


def to_display(image: np.ndarray, curve: str, exposure: float) -> np.ndarray:
    """Tone-map (lenslab.tone) then sRGB-encode (colour-science) to 3-channel float32 in [0, 1]."""
    import warnings

    from lenslab.io.encode import encode_srgb
    from lenslab.tone import tonemap

    img = as_image(image, "image").astype(np.float32, copy=False)
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

    r, t, m = paired_images(ref, test, mask)
    params = {} if ppd is None else {"ppd": float(ppd)}
    rd = np.where(m[..., None], to_display(r, curve, exposure), 0.0).astype(np.float32)
    td = np.where(m[..., None], to_display(t, curve, exposure), 0.0).astype(np.float32)
    fmap, _, _ = flip_evaluator.evaluate(rd, td, "LDR", inputsRGB=True, applyMagma=False,
                                         computeMeanError=False, parameters=params)
    fmap = np.asarray(fmap, dtype=np.float32).reshape(r.shape[:2])
    mean = float(fmap[m].mean()) if m.any() else float("nan")
    return (mean, fmap) if return_map else mean
