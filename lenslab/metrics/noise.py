"""The Monte Carlo noise floor of a traced reference: the relative L1 its noise alone gives, from its
standard error or from two independent half renders; see :mod:`lenslab.metrics`."""

from __future__ import annotations

import math

import numpy as np

from lenslab.metrics.measures import as_image, paired_images


def noise_floor(ref, ref_stderr, mask=None) -> dict[str, float]:
    """What the reference's own Monte Carlo noise alone contributes to the metrics.

    ``ref_stderr`` is the per-pixel, per-channel standard error of the reference's mean (same shape as
    the reference, or ``H x W`` for all channels); for a renderer reporting the sample variance ``var``
    of ``n`` samples per pixel pass ``sqrt(var / n)``.

    Returns ``l1`` (expected relative L1 of the noise against an exact image: ``sqrt(2/pi) sum sigma /
    sum |r|``), ``rmse`` (``sqrt(mean sigma^2)``) and ``relative_stderr`` (``sqrt(sum sigma^2) / sum |r|``,
    the standard error of the image mean, relative).
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


def noise_floor_split(half_a, half_b, mask=None) -> float:
    """Expected relative L1 of the noise of ``(half_a + half_b) / 2`` against the exact image.

    ``half_a`` and ``half_b`` are two independent renders with half the samples each (different seeds).
    Their difference ``(n_a - n_b)/2`` has the distribution of the noise of their mean when the noise is
    symmetric, whatever its shape, so ``sum |a - b| / 2 / sum |(a + b)/2|`` estimates the noise L1
    without assuming normality. (Monte Carlo noise at a few samples per pixel is heavy-tailed: there
    the normal formula of :func:`noise_floor` overestimates the L1, by about 2x at 16 spp.)
    """
    a, b, m = paired_images(half_a, half_b, mask)
    if not m.any():
        return float("nan")
    den = float(np.abs(0.5 * (a[m] + b[m])).sum())
    if den == 0.0:
        return float("nan")
    return 0.5 * float(np.abs(a[m] - b[m]).sum()) / den
