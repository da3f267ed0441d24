"""Masks of the pixels to compare, and the scalar error measures of a test image against a reference
(relative L1, RMSE, PSNR of log radiance, the share off by more than 5%, FLIP); see :mod:`lenslab.metrics`."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

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


def valid_mask(ref_alpha: ArrayLike | None = None, test_alpha: ArrayLike | None = None,
               shape: tuple[int, int] | None = None, threshold: float = FULL_COVERAGE) -> np.ndarray:
    """Pixels fully covered in both images: ``ref_alpha >= threshold`` and ``test_alpha >= threshold``.

    Parameters
    ----------
    ref_alpha, test_alpha : array_like, optional
        Coverage ``H x W`` (or ``H x W x 1``) of each image; None: everything covered. Pixels with a
        non-finite alpha are excluded.
    shape : tuple of int, optional
        (H, W), needed when both alphas are None.
    threshold : float
        The coverage that counts as full (alpha is a sample fraction; 0.999 by default).

    Returns
    -------
    numpy.ndarray
        bool ``H x W``.

    Raises
    ------
    ValueError
        Neither an alpha nor a shape, or an alpha of another shape.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import valid_mask
    >>> valid_mask(np.array([[1.0, 0.5]]), np.array([[1.0, 1.0]])).tolist()
    [[True, False]]
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
def relative_l1(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None) -> float:
    """Aggregate relative L1 ``sum |t - r| / sum |r|`` over masked pixels and all channels.

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare (all by default; :func:`valid_mask` gives the fully
        covered ones). Pixels with a non-finite value in either image never count.

    Returns
    -------
    float
        NaN when the mask is empty, 0 when both images are 0 there, inf when only the reference is.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import relative_l1
    >>> relative_l1(np.array([[1.0, 3.0]]), np.array([[1.5, 3.0]]))  # 0.5 / 4
    0.125
    """
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    num = float(np.abs(t[m] - r[m]).sum())
    den = float(np.abs(r[m]).sum())
    if den == 0.0:
        return 0.0 if num == 0.0 else float("inf")
    return num / den


def rmse(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None) -> float:
    """Root mean squared difference over masked pixels and channels (linear radiance units).

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare (all by default; :func:`valid_mask` gives the fully
        covered ones). Pixels with a non-finite value in either image never count.

    Returns
    -------
    float
        NaN when the mask is empty.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import rmse
    >>> rmse(np.zeros((2, 2)), np.array([[0.0, 2.0], [0.0, 0.0]]))  # sqrt(4 / 4)
    1.0
    """
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    return float(np.sqrt(np.mean((t[m] - r[m]) ** 2)))


def psnr_log(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None, floor: float = 1e-3) -> float:
    """PSNR (dB) of log radiance: ``10 log10(peak^2 / mean((log(t+e) - log(r+e))^2))``.

    ``e`` is ``floor`` times the mean reference value and ``peak`` the range of ``log(r+e)`` over the
    mask (one e-fold for a flat reference): an error in a shadow weighs like the same relative error
    in a highlight.

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare (all by default; :func:`valid_mask` gives the fully
        covered ones). Pixels with a non-finite value in either image never count.
    floor : float
        The offset ``e`` as a fraction of the mean reference value (keeps black pixels finite).

    Returns
    -------
    float
        Decibels; inf for identical images, NaN when the mask is empty.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    A test image 10% too bright everywhere, on a reference spanning 1 to e (one e-fold), is off by
    ``log 1.1`` in every pixel (``e`` aside): 20 log10(1 / log 1.1) = 20.4 dB.

    >>> import math, numpy as np
    >>> from lenslab.metrics import psnr_log
    >>> ref = np.array([[1.0, math.e]])
    >>> round(psnr_log(ref, ref * 1.1, floor=0.0), 6) == round(20 * math.log10(1 / math.log(1.1)), 6)
    True
    >>> psnr_log(ref, ref)
    inf
    """
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


def share_off(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None, tolerance: float = 0.05,
              floor_fraction: float = 0.01) -> float:
    """Fraction of masked pixels whose relative error exceeds ``tolerance`` (5% by default).

    A pixel's relative error is ``sum_c |t - r| / max(sum_c |r|, floor)``, ``floor`` being
    ``floor_fraction`` times the mean pixel sum, so that near-black pixels are judged by an absolute
    error instead of dividing by zero.

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare (all by default; :func:`valid_mask` gives the fully
        covered ones). Pixels with a non-finite value in either image never count.
    tolerance : float
        The relative error a pixel may have.
    floor_fraction : float
        The floor of the denominator, as a fraction of the mean pixel sum.

    Returns
    -------
    float
        In [0, 1]; NaN when the mask is empty.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import share_off
    >>> share_off(np.ones((1, 4)), np.array([[1.0, 1.01, 1.0, 1.1]]))  # one pixel of four is 10% off
    0.25
    """
    r, t, m = paired_images(ref, test, mask)
    if not m.any():
        return float("nan")
    e = pixel_relative_error(r, t, floor_fraction)
    return float(np.mean(e[m] > tolerance))


def error_map(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None,
              floor_fraction: float = 0.01) -> np.ndarray:
    """Per-pixel relative error for display: ``sum_c |t - r| / max(sum_c |r|, floor)``.

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to show.
    floor_fraction : float
        The floor of the denominator, as a fraction of the mean pixel sum (as :func:`share_off`).

    Returns
    -------
    numpy.ndarray
        float32 ``H x W``; NaN outside the mask.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import error_map
    >>> error_map(np.array([[1.0, 2.0]]), np.array([[1.5, 2.0]]), mask=np.array([[True, False]])).tolist()
    [[0.5, nan]]
    """
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


def flip(ref: ArrayLike, test: ArrayLike, mask: ArrayLike | None = None, curve: str = "hable",
         exposure: float = 0.0, return_map: bool = False,
         ppd: float | None = None) -> float | tuple[float, np.ndarray]:
    """Mean LDR-FLIP error over the mask of the two images tone-mapped alike (0 = identical, 1 = worst).

    Both images go through :func:`lenslab.tone.tonemap` with the same ``curve`` and ``exposure`` and the
    sRGB encoding, then ``flip_evaluator.evaluate(..., "LDR")`` (NVIDIA's FLIP); the per-pixel map is
    averaged over the mask (FLIP itself sees the whole image, since its filters span neighbouring
    pixels).

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare (all by default; :func:`valid_mask` gives the fully
        covered ones). Pixels with a non-finite value in either image never count.
    curve : str
        The tone curve both images go through (a name of :data:`lenslab.tone.CURVES`).
    exposure : float
        Exposure in stops before the curve.
    return_map : bool
        Also return the per-pixel map.
    ppd : float, optional
        FLIP's pixels per degree of the viewer (FLIP's default, 67: a 0.7 m wide 4K screen seen from 0.7 m).

    Returns
    -------
    float or tuple of (float, numpy.ndarray)
        The mean; with ``return_map``, ``(mean, map)``, the map float32 ``H x W``.

    Raises
    ------
    ValueError
        Images of different shapes, or a mask of another size.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import flip
    >>> image = np.linspace(0.0, 4.0, 8 * 8 * 3, dtype=np.float32).reshape(8, 8, 3)
    >>> flip(image, image)
    0.0
    >>> 0.0 < flip(image, image * 2.0) < 1.0
    True
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
