"""Exposure: luminance weights, log-averages and automatic exposure.

Exposure is in stops, ``x * 2**EV``. ``auto`` picks EV so that the log-average luminance, with the
darkest and brightest percent of the positive pixels left out, lands on middle grey (0.18); an image with
alpha is measured on its covered pixels' straight colour, each counted by its coverage.
Luminance weights are the Y row of the image's RGB -> XYZ matrix: the sRGB standard's own for sRGB
(the default), from chromaticities by SMPTE RP 177, or from colour-science for any other colourspace name.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import ToneError

F32 = np.float32
MIDDLE_GREY = 0.18
#: exposure accepted, in stops (2**100 and 2**-100 are still ordinary float32 numbers)
EXPOSURE_RANGE = (-100.0, 100.0)
# the Y row of IEC 61966-2-1's own RGB -> XYZ matrix (rounded to 4 digits there; colour-science's sRGB
# colourspace uses the same published matrix)
_KNOWN_WEIGHTS = {"sRGB": (0.2126, 0.7152, 0.0722)}


def _luminance_row(xy: np.ndarray) -> np.ndarray:
    """The Y row of the RGB -> XYZ matrix of primaries and white point ``xy`` ((4, 2): R, G, B, W),
    as SMPTE RP 177 derives it (what colour-science's ``normalised_primary_matrix`` computes)."""
    xyz = np.column_stack([xy[:, 0], xy[:, 1], 1.0 - xy[:, 0] - xy[:, 1]]) / xy[:, 1:2]  # X/Y, 1, Z/Y
    try:
        gains = np.linalg.solve(xyz[:3].T, xyz[3])
    except np.linalg.LinAlgError:
        raise ToneError(f"primaries {xy.tolist()} are not usable: the three colours are not independent") from None
    return gains  # the Y of each primary is 1 before scaling: the Y row is the gains


@functools.lru_cache(maxsize=32)
def _weights_by_name(name: str) -> tuple[float, float, float]:
    if name in _KNOWN_WEIGHTS:  # no colour-science import (a second) for the common case
        return _KNOWN_WEIGHTS[name]
    from lenslab.srgb import colour_science

    colour = colour_science()

    if name not in colour.RGB_COLOURSPACES:
        close = [n for n in colour.RGB_COLOURSPACES if name.lower() in n.lower()][:8]
        hint = f" (close: {', '.join(close)})" if close else " such as sRGB, ITU-R BT.2020, ACEScg, Display P3"
        raise ToneError(f"unknown RGB colourspace {name!r} for luminance weights; use a colour-science "
                        f"colourspace name{hint}")
    return tuple(float(v) for v in colour.RGB_COLOURSPACES[name].matrix_RGB_to_XYZ[1])


def luminance_weights(primaries: str = "sRGB") -> np.ndarray:
    """Luminance weights (Y row of RGB -> XYZ) from colour-science, float32 (3,).

    ``primaries``: a colour-science colourspace name (``"sRGB"``: Rec.709, 0.2126 0.7152 0.0722),
    chromaticities ``((xr, yr), (xg, yg), (xb, yb), (xw, yw))`` as an EXR header stores them, or
    three weights directly.
    """
    if primaries is None:
        primaries = "sRGB"
    if isinstance(primaries, str):
        return np.array(_weights_by_name(primaries), dtype=F32)
    arr = np.asarray(primaries, dtype=np.float64)
    if arr.shape == (3,):
        w = arr
    elif arr.shape == (4, 2):
        w = _luminance_row(arr)
    else:
        raise ToneError(f"primaries must be a colourspace name, 4 (x, y) chromaticities or 3 weights; "
                        f"got shape {arr.shape}")
    if not np.all(np.isfinite(w)) or np.any(w < 0) or w.sum() <= 0:
        raise ToneError(f"luminance weights {w.tolist()} are not usable: they must be finite and >= 0")
    return w.astype(F32)


def luminance_sample(image: np.ndarray, weights, max_samples: int = 1 << 18, alpha: bool | None = None) -> np.ndarray:
    """Luminance of (an evenly strided sample of) the image, float64, bad values as in tonemap
    (NaN and negatives count as 0, pixels with a +inf channel are dropped); a trailing alpha
    (:func:`lenslab.io.alpha.alpha_last`) is left out."""
    from lenslab.io.alpha import alpha_last

    x = np.asarray(image)
    if x.ndim == 3 and alpha_last(x.shape[-1], alpha):
        x = x[..., :-1]
    channels = 3 if x.ndim == 3 and x.shape[-1] == 3 else 1
    px = x.reshape(-1, channels)
    step = max(1, -(-px.shape[0] // max_samples))
    planes = np.array(px[::step].T, dtype=np.float64)  # (channels, n): contiguous rows
    finite = np.ones(planes.shape[1], bool)
    for row in planes:
        finite &= ~np.isposinf(row)
    np.nan_to_num(planes, copy=False, nan=0.0, posinf=0.0, neginf=0.0)
    np.clip(planes, 0.0, None, out=planes)
    if channels == 3:
        w = np.asarray(weights, dtype=np.float64)
        lum = planes[0] * w[0] + planes[1] * w[1] + planes[2] * w[2]
    else:
        lum = planes[0]
    return lum[finite]


def covered_luminance(image: np.ndarray, weights, max_samples: int = 1 << 18) -> tuple[np.ndarray, np.ndarray]:
    """(luminance of the straight colour, coverage) of the covered pixels (alpha > 0) of (an evenly
    strided sample of) an image with alpha last (H x W x C, colour premultiplied), float64; bad values as
    in :func:`luminance_sample`, alpha clipped to [0, 1] (NaN: 0)."""
    x = np.asarray(image)
    px = x.reshape(-1, x.shape[-1])
    step = max(1, -(-px.shape[0] // max_samples))
    sample = np.array(px[::step], dtype=np.float64)
    a = np.clip(np.nan_to_num(sample[:, -1], nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    covered = a > 0
    colour = sample[covered, :-1] / a[covered, None]
    lum = luminance_sample(colour[:, None, :], weights if colour.shape[1] == 3 else None, colour.shape[0] + 1,
                           alpha=False)
    finite = ~np.isposinf(colour).any(axis=1)
    return lum, a[covered][finite]


def log_average(lum: np.ndarray, trim: float = 0.0, delta: float | None = None,
                weights: np.ndarray | None = None) -> float:
    """Log-average (geometric mean) of luminance values, each counted by its ``weights`` (an image with
    alpha: the coverage; None: all 1).

    ``delta=None``: over the positive values only, with the ``trim`` percent darkest and brightest of
    them (by weight) left out (0 when there are none). ``delta > 0``: Reinhard et al.'s
    ``exp(mean(log(delta + L)))`` over every value.
    """
    lum = np.asarray(lum, dtype=np.float64).reshape(-1)
    w = None if weights is None else np.asarray(weights, dtype=np.float64).reshape(-1)
    if delta is not None:
        if not lum.size or (w is not None and not w.sum() > 0):
            return 0.0
        return float(np.exp(np.average(np.log(delta + lum), weights=w)))
    positive = lum > 0
    logs = np.log2(lum[positive])
    if w is not None:
        w = w[positive]
        logs, w = logs[w > 0], w[w > 0]
    if logs.size == 0:
        return 0.0
    if trim > 0:
        lo, hi = np.percentile(logs, [trim, 100.0 - trim]) if w is None else _weighted_bounds(logs, w, trim)
        kept = (logs >= lo) & (logs <= hi)
        if kept.any():
            logs, w = logs[kept], (None if w is None else w[kept])
    return float(2.0 ** np.average(logs, weights=w))


def _weighted_bounds(logs: np.ndarray, w: np.ndarray, trim: float) -> tuple[float, float]:
    """The ``trim`` and ``100 - trim`` percentiles of ``logs`` weighted by ``w`` (the inverse of the
    weighted cumulative distribution, NumPy's ``inverted_cdf`` method): the first value whose
    cumulative weight reaches the share."""
    order = np.argsort(logs, kind="stable")
    values, cum = logs[order], np.cumsum(w[order])
    last = values.size - 1
    lo = values[min(int(np.searchsorted(cum, cum[-1] * trim / 100.0)), last)]
    hi = values[min(int(np.searchsorted(cum, cum[-1] * (1.0 - trim / 100.0))), last)]
    return float(lo), float(hi)


def auto_exposure(image: ArrayLike, key: float = MIDDLE_GREY, trim: float = 1.0, primaries: str = "sRGB",
                  alpha_channel: bool | None = None) -> float:
    """Exposure in stops that brings the image's log-average luminance to ``key`` (middle grey).

    The average is taken over positive pixels (black borders, e.g. outside a fisheye circle, are
    not scene content), with the ``trim`` percent darkest and brightest left out: a small sun of
    30000 does not drag the rest into black. An image with no positive pixel gets 0 (it stays black).
    The result is limited to :data:`EXPOSURE_RANGE`.

    An image with alpha is measured as a compositor sees its covered pixels: the luminance of each
    pixel's *straight* colour (premultiplied colour / alpha), counted by its coverage,
    ``2 ** (sum(a * log2 L) / sum(a))`` over the pixels with ``a > 0`` (the trim by coverage too, NumPy's
    weighted ``inverted_cdf`` percentiles; when every covered pixel has the same alpha, the statistic of
    an image without alpha).
    Premultiplied colour would count a pixel half covered by a sky of 4.0 as a dark pixel of 2.0, a
    value the scene does not hold, and brighten the whole image for its transparent edge; straight colour
    counted as a whole pixel would give a pixel 1 % covered (its colour divided by 0.01: quantisation and
    noise a hundred times) the weight of a covered one.

    Parameters
    ----------
    image : array_like
        Scene-linear, ``H x W x 3`` (or 4, alpha ignored) or grey.
    key : float
        The luminance the log-average should land on (0.18, middle grey).
    trim : float
        Percent of the darkest and of the brightest positive pixels left out, in [0, 50).
    primaries : str
        The RGB primaries whose luminance weights apply: a colour-science colourspace name
        (``"sRGB"``, ``"ITU-R BT.2020"``...) or an EXR header's chromaticities.
    alpha_channel : bool, optional
        Whether the last channel is alpha (what the channel names say); None: 2 or 4 channels carry it
        (:func:`lenslab.io.alpha.alpha_last`).

    Returns
    -------
    float
        Stops, as :func:`lenslab.tone.tonemap`'s ``exposure`` takes them.

    Raises
    ------
    lenslab.errors.ToneError
        A ``trim`` out of range or a ``key`` that is not positive.

    Examples
    --------
    A flat grey of 0.72 is two stops above middle grey (0.72 / 4 = 0.18):

    >>> import numpy as np
    >>> from lenslab.tone import auto_exposure
    >>> auto_exposure(np.full((8, 8, 3), 0.72))
    -2.0
    """
    if not 0 <= trim < 50:
        raise ToneError(f"auto exposure: trim={trim:g} must be a percentage in [0, 50)")
    if not key > 0:
        raise ToneError(f"auto exposure: key={key:g} must be > 0 (middle grey is 0.18)")
    from lenslab.io.alpha import alpha_last

    x = np.asarray(image)
    alpha = x.ndim == 3 and alpha_last(x.shape[-1], alpha_channel)
    colour_image = x.ndim == 3 and x.shape[-1] - alpha == 3
    weights = luminance_weights(primaries) if colour_image else None
    if alpha:  # the straight colour of the covered pixels, each counted by its coverage
        lum, coverage = covered_luminance(x, weights)
        # all covered alike (alpha 1): the very statistic of an image without alpha (its trim interpolates)
        avg = log_average(lum, trim=trim, weights=None if np.all(coverage == coverage[:1]) else coverage)
    else:
        avg = log_average(luminance_sample(x, weights, alpha=False), trim=trim)
    if avg <= 0:
        return 0.0
    return float(np.clip(math.log2(key / avg), *EXPOSURE_RANGE))


def parse_exposure(exposure, image, primaries, alpha: bool | None = None) -> float:
    if isinstance(exposure, str):
        text = exposure.strip().lower()
        if text == "auto":
            return auto_exposure(image, primaries=primaries, alpha_channel=alpha)
        try:
            exposure = float(text)
        except ValueError:
            raise ToneError(f"exposure {exposure!r} is neither a number of stops nor 'auto'") from None
    try:
        ev = float(exposure)
    except (TypeError, ValueError):
        raise ToneError(f"exposure {exposure!r} is neither a number of stops nor 'auto'") from None
    if not EXPOSURE_RANGE[0] <= ev <= EXPOSURE_RANGE[1]:
        raise ToneError(f"exposure {ev:g} stops is out of range; give a number in "
                        f"[{EXPOSURE_RANGE[0]:g}, {EXPOSURE_RANGE[1]:g}] or 'auto'")
    return ev

