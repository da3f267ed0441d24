"""The Monte Carlo noise floor of a traced reference: the relative L1 its noise alone gives, from its
standard error or from two independent half renders; see :mod:`lenslab.metrics`."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from lenslab.metrics.measures import as_image, paired_images


def noise_floor(ref: ArrayLike, ref_stderr: ArrayLike, mask: ArrayLike | None = None) -> dict[str, float]:
    """What the reference's own Monte Carlo noise alone contributes to the metrics.

    Parameters
    ----------
    ref : array_like
        The traced reference, ``H x W x C`` or ``H x W``.
    ref_stderr : array_like
        The per-pixel, per-channel standard error of the reference's mean (the reference's shape, or
        ``H x W`` for all channels); for a renderer reporting the sample variance ``var`` of ``n``
        samples per pixel pass ``sqrt(var / n)``.
    mask : array_like, optional
        Boolean ``H x W``: the pixels compared.

    Returns
    -------
    dict
        ``l1``, the expected relative L1 of the noise against an exact image (``sqrt(2/pi) sum sigma /
        sum |r|``, the mean absolute value of a normal variable), ``rmse`` (``sqrt(mean sigma^2)``) and
        ``relative_stderr`` (``sqrt(sum sigma^2) / sum |r|``, the standard error of the image mean,
        relative). NaN where the mask is empty or the reference is 0.

    Examples
    --------
    >>> import math, numpy as np
    >>> from lenslab.metrics import noise_floor
    >>> floor = noise_floor(np.full((4, 4), 2.0), np.full((4, 4), 0.1))
    >>> floor["l1"] == math.sqrt(2 / math.pi) * 0.1 / 2.0, floor["rmse"]
    (True, 0.1)
    """
    r = as_image(ref, "reference").astype(np.float64, copy=False)
    s = as_image(ref_stderr, "reference standard error").astype(np.float64, copy=False)
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


def noise_floor_split(half_a: ArrayLike, half_b: ArrayLike, mask: ArrayLike | None = None) -> float:
    """Expected relative L1 of the noise of ``(half_a + half_b) / 2`` against the exact image.

    ``half_a`` and ``half_b`` are two independent renders with half the samples each (different seeds).
    Their difference ``(n_a - n_b)/2`` has the distribution of the noise of their mean when the noise is
    symmetric, whatever its shape, so ``sum |a - b| / 2 / sum |(a + b)/2|`` estimates the noise L1
    without assuming normality. (Monte Carlo noise at a few samples per pixel is heavy-tailed: there
    the normal formula of :func:`noise_floor` overestimates the L1, by about 2x at 16 spp.)

    Parameters
    ----------
    half_a, half_b : array_like
        The two half renders, of one shape.
    mask : array_like, optional
        Boolean ``H x W``: the pixels compared.

    Returns
    -------
    float
        ``sum |a - b| / 2 / sum |(a + b) / 2|``; NaN when the mask is empty or the mean is 0.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import noise_floor_split
    >>> noise_floor_split(np.array([[0.9, 1.1]]), np.array([[1.1, 0.9]]))  # 0.2 / 2 / 1, float64 rounding aside
    0.10000000000000003
    """
    a, b, m = paired_images(half_a, half_b, mask)
    if not m.any():
        return float("nan")
    den = float(np.abs(0.5 * (a[m] + b[m])).sum())
    if den == 0.0:
        return float("nan")
    return 0.5 * float(np.abs(a[m] - b[m]).sum()) / den
