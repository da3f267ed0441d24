"""``tonemap``: the one entry point; repair, exposure and curve in a fixed order.

``tonemap(image, curve="hable", exposure=0.0, mode="per-channel", **params)`` returns display-linear
float32 (not yet sRGB-encoded: ``lenslab.io.write`` encodes). The order of work is fixed:

1. bad values are repaired and counted: NaN -> 0, +inf -> white, negatives (and -inf) -> 0; when there
   were any, a :class:`ToneWarning` carrying the counts is issued (never silently), except for slight
   negatives alone (a lossy codec's undershoot, :mod:`lenslab.tone.repairs`), which are tallied for
   one line at the end of a command;
2. exposure in stops, ``x * 2**EV``; ``exposure="auto"`` picks EV so that the log-average luminance,
   with the darkest and brightest percent of the pixels left out, lands on middle grey (0.18);
3. the curve, either on each channel (``mode="per-channel"``) or on luminance (``mode="luminance"``:
   RGB is scaled by ``curve(L) / L``, which keeps the ratios between channels, i.e. the hue; a pixel
   whose brightest channel would then pass 1 is blended toward grey of the same luminance until it
   fits, so luminance and hue angle survive and only saturation gives way).
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import ToneError
from lenslab.tone.exposure import (
    log_average,
    luminance_sample,
    luminance_weights,
    parse_exposure,
)
from lenslab.tone.repairs import SLIGHT, add as tally_slight, slight
from lenslab.tone.kernels import F32
from lenslab.tone.registry import get_curve
from lenslab.tone.sweep import Counts, repair, run_split, sweep_luminance, sweep_rgb, sweep_values


class ToneWarning(UserWarning):
    """Bad input values were repaired while tone mapping. ``nan``, ``posinf`` and ``negative`` hold
    the counts (negative includes -inf); ``total`` is the number of values looked at."""

    def __init__(self, message: str, nan: int = 0, posinf: int = 0, negative: int = 0, total: int = 0):
        super().__init__(message)
        self.nan, self.posinf, self.negative, self.total = int(nan), int(posinf), int(negative), int(total)



def warn_repairs(counts: Counts, total: int, image=None) -> None:
    """A ToneWarning for NaN, +inf and real negatives; slight negatives alone (a codec's undershoot,
    :func:`lenslab.tone.repairs.slight`, judged on ``image``) go to the command's one-line tally instead."""
    if not counts.any():
        return
    if not counts.nan and not counts.posinf and slight(image if image is not None else (), counts.lowest):
        tally_slight(counts.negative, counts.lowest)
        return
    parts = []
    if counts.nan:
        parts.append(f"{counts.nan} NaN set to 0")
    if counts.posinf:
        parts.append(f"{counts.posinf} +inf set to white")
    if counts.negative:
        # "slightly": no lower than repairs.SLIGHT (a codec's or filter's undershoot), as against real negative light
        how = "slightly negative" if counts.lowest >= -SLIGHT else "negative"
        parts.append(f"{counts.negative} {how} value{'s' if counts.negative != 1 else ''}, down to "
                     f"{counts.lowest:.2g}, set to 0")
    msg = f"tone mapping repaired {', '.join(parts)} (of {total} values)"
    warnings.warn(ToneWarning(msg, counts.nan, counts.posinf, counts.negative, total), stacklevel=3)


def as_float32(image) -> np.ndarray:
    x = np.asarray(image)
    if x.dtype != F32:
        x = x.astype(F32)
    return np.ascontiguousarray(x)


def tonemap(image: ArrayLike, curve: str = "hable", exposure: float | str = 0.0, mode: str = "per-channel",
            *, primaries: str = "sRGB", threads: int | None = None, in_place: bool = False,
            **params: float) -> np.ndarray:
    """Tone-map scene-linear ``image`` to display-linear float32 in [0, 1] (same shape).

    The order of work is fixed: bad values are repaired, then the exposure, then the curve (see the
    module's description). ``lenslab.write`` sRGB-encodes the result for LDR files.

    Parameters
    ----------
    image : array_like
        ``H x W x C`` (``C`` = 1, 3; 2 or 4 with alpha last, colour premultiplied as in OpenEXR: the
        curve acts on the unpremultiplied colour and alpha passes through clipped to [0, 1]), or any
        array of single-channel values.
    curve : str
        A name in :data:`lenslab.tone.CURVES` (``lenslab curves`` draws them all).
    exposure : float or "auto"
        Stops, ``x * 2**exposure``; ``"auto"`` brings the log-average luminance to middle grey (0.18).
    mode : str
        ``"per-channel"``, or ``"luminance"`` (the curve on luminance, keeping the hue).
    primaries : str
        The RGB primaries, for the luminance weights (:func:`lenslab.tone.luminance_weights`).
    threads : int, optional
        Threads that share a large image (None: every core this process may use); the result does not
        depend on it.
    in_place : bool
        The caller gives ``image`` up (a float32 array): the result may be written in its memory and
        returned, with no output array of the image's size (the same values).
    **params
        The curve's own parameters (``lenslab curves`` and :data:`lenslab.tone.CURVES` list them).

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``image``.

    Raises
    ------
    lenslab.errors.ToneError
        An unknown curve, mode or parameter (the message lists the valid ones), or a parameter out of
        range.

    Warns
    -----
    ToneWarning
        NaN, infinite or negative values were repaired (NaN and negatives to 0, +inf to white); the
        warning carries their counts.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.tone import tonemap
    >>> tonemap(np.array([0.0, 1.0, 4.0], np.float32), "reinhard").tolist()   # x / (1 + x)
    [0.0, 0.5, 0.800000011920929]
    >>> tonemap(np.array([0.25], np.float32), "clamp", exposure=1).tolist()    # 0.25 * 2**1
    [0.5]
    """
    spec = get_curve(curve)
    resolved = spec.resolve(params)
    mode_key = str(mode).strip().lower()
    if mode_key not in ("per-channel", "luminance"):
        raise ToneError(f"tone mode {mode!r} is not valid; use 'per-channel' or 'luminance'")
    x = as_float32(image)
    if x.ndim == 3 and x.shape[-1] not in (1, 2, 3, 4):
        raise ToneError(f"image has {x.shape[-1]} channels; tone mapping takes 1 or 3 (plus alpha)")
    if x.ndim == 3 and x.shape[-1] in (2, 4):
        alpha = np.clip(np.nan_to_num(x[..., -1], nan=0.0, posinf=1.0, neginf=0.0), 0, 1)
        colour_part = x[..., :-1].copy()
        a = alpha[..., None]
        np.divide(colour_part, a, out=colour_part, where=a > 0)
        mapped = tonemap(colour_part, spec.name, exposure, mode_key, primaries=primaries, threads=threads,
                         in_place=True, **resolved)  # (the copy is this function's own)
        del colour_part
        mapped *= a
        out = x if _own(image, x, in_place) else np.empty(x.shape, F32)
        out[..., :-1] = mapped
        del mapped
        out[..., -1] = alpha
        return out

    ev = parse_exposure(exposure, x, primaries)
    scale = 2.0 ** ev
    rgb = x.ndim == 3 and x.shape[-1] == 3
    # luminance weights only where something weighs channels (importing colour-science takes a while)
    needs_weights = spec.kind == "local" or (rgb and (mode_key == "luminance" or spec.kind == "image"))
    weights = luminance_weights(primaries) if needs_weights else None
    counts = Counts()

    if spec.kind == "local":
        clean = x.copy()
        inf_mask = repair(clean, counts)
        clean *= F32(scale)
        out = spec.build(clean, resolved, weights)
        out[inf_mask.any(axis=-1) if rgb else inf_mask] = 1
        warn_repairs(counts, x.size, x)
        return out

    if spec.kind == "image":
        # Reinhard et al. 2002: the scale key / log-average comes from the image's luminance
        lum = luminance_sample(x, weights) * scale
        avg = log_average(lum, delta=resolved["delta"]) if lum.size else 1.0
        scale = scale * resolved["key"] / max(avg, 1e-30)

    # in place where each block is read before it is written (per value, or RGB through planar copies)
    # and the warning need not look at the input again (no negative beyond the slight ones)
    out = x if (_own(image, x, in_place) and x.flags.c_contiguous and (mode_key == "per-channel" or not rgb)
                and x.size and bool(x.min() >= -SLIGHT)) else np.empty_like(x)
    with np.errstate(divide="ignore", over="ignore"):
        _apply_global(spec, resolved, scale, x, out, rgb, mode_key, weights, counts, threads)
    warn_repairs(counts, x.size, x)
    return out


def _own(image, x: np.ndarray, in_place: bool) -> bool:
    """Whether ``x`` (``image`` as float32) may hold the result: the caller gave ``image`` up, or ``x`` is
    a copy made here."""
    return (in_place or x is not image) and x.flags.writeable


def _apply_global(spec, resolved, scale, x, out, rgb, mode_key, weights, counts, threads):
    if spec.kind == "rgb" and rgb and mode_key == "per-channel":
        sweep, kernel, extra = sweep_rgb, spec.build(resolved, scale), ()
    else:
        # an RGB curve on grey values or on luminance takes its grey form
        kernel = spec.build_grey(resolved, scale) if spec.kind == "rgb" else spec.build(resolved, scale)
        if rgb and mode_key == "luminance":
            sweep, extra = sweep_luminance, (weights,)
        else:
            sweep, extra = sweep_values, ()
    src = x.reshape(-1, 3) if sweep is not sweep_values else x.reshape(-1)
    dst = out.reshape(src.shape)
    run_split(sweep, src, dst, kernel, extra, counts, threads)


def values(curve: str, x, params) -> np.ndarray:
    arr = as_float32(x)
    out = tonemap(arr.reshape(-1), curve, 0.0, "per-channel", **params)
    return out.reshape(arr.shape)


def triples(curve: str, x, params) -> np.ndarray:
    arr = as_float32(x)
    if arr.ndim >= 1 and arr.shape[-1] == 3:
        return tonemap(arr.reshape(-1, 1, 3), curve, 0.0, "per-channel", **params).reshape(arr.shape)
    return values(curve, arr, params)

