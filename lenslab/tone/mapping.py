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
from lenslab.io.alpha import alpha_last
from lenslab.tone.exposure import (
    covered_luminance,
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


class ExposureIgnoredWarning(UserWarning):
    """An exposure was given to a curve whose result is the same for any exposure (its record's
    ``ignores_exposure`` says why)."""



def warn_repairs(counts: Counts, total: int, image=None, is_slight: bool | None = None,
                 lead: str = "tone mapping repaired") -> None:
    """A ToneWarning for NaN, +inf and real negatives; slight negatives alone (a codec's undershoot,
    :func:`lenslab.tone.repairs.slight`, judged on ``image``, or ``is_slight`` as already judged band by
    band) go to the command's one-line tally instead. ``lead``: what repaired them, the note's first words."""
    if not counts.any():
        return
    if is_slight is None:
        is_slight = slight(image if image is not None else (), counts.lowest)
    if not counts.nan and not counts.posinf and is_slight:
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
    msg = f"{lead} {', '.join(parts)} (of {total} values)"
    warnings.warn(ToneWarning(msg, counts.nan, counts.posinf, counts.negative, total), stacklevel=3)


def warn_negatives(values: np.ndarray, lead: str) -> None:
    """The note a display output gives for the negatives ``values`` (float, the colour of an image) hold, for
    an output that sets them to 0 without tone mapping (Radiance RGBE): real negatives a ToneWarning that
    starts with ``lead``, slight ones the command's tally (:func:`warn_repairs`)."""
    if not values.size or not np.fmin.reduce(values, axis=None) < 0:  # fmin passes NaN by: a NaN hides no negative
        return
    counts = Counts()
    negative = values < 0
    negative &= values != -np.inf  # -inf is the writer's note on non-finite samples
    if not negative.any():
        return
    counts.negative, counts.lowest = int(np.count_nonzero(negative)), float(values[negative].min())
    warn_repairs(counts, values.size, image=values, lead=lead)


def as_float32(image) -> np.ndarray:
    x = np.asarray(image)
    if x.dtype != F32:
        x = x.astype(F32)
    return np.ascontiguousarray(x)


def tonemap(image: ArrayLike, curve: str = "hable", exposure: float | str = 0.0, mode: str = "per-channel",
            *, primaries: str = "sRGB", threads: int | None = None, in_place: bool = False,
            alpha_channel: bool | None = None, **params: float) -> np.ndarray:
    """Tone-map scene-linear ``image`` to display-linear float32 in [0, 1] (same shape).

    The order of work is fixed: bad values are repaired, then the exposure, then the curve (see the
    module's description). ``lenslab.write`` sRGB-encodes the result for LDR files.

    Parameters
    ----------
    image : array_like
        ``H x W x C`` (``C`` = 1, 3, or one more with alpha last, colour premultiplied as in OpenEXR: the
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
    alpha_channel : bool, optional
        Whether the last channel is alpha (what the image's channel names say: only ``A`` is alpha);
        None: an image of 2 or 4 channels carries it (:func:`lenslab.io.alpha.alpha_last`, the rule the
        warp APIs follow). ``False``: every channel is mapped as a value (``u, v`` or ``R, G, B, Z``).
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
    if x.ndim == 0:
        return tonemap(x.reshape(1), spec.name, exposure, mode_key, primaries=primaries, **resolved).reshape(())
    if x.ndim == 3 and x.shape[-1] not in (1, 2, 3, 4):
        raise ToneError(f"image has {x.shape[-1]} channels; tone mapping takes 1 or 3 (plus alpha)")
    alpha = x.ndim == 3 and alpha_last(x.shape[-1], alpha_channel)
    if spec.kind == "local":
        return _local(image, x, spec, resolved, exposure, mode_key, primaries, threads, in_place, alpha)
    colour = x.shape[-1] - 1 if alpha else (x.shape[-1] if x.ndim == 3 else 1)
    rgb = x.ndim == 3 and colour == 3
    # the statistics (auto exposure, an image curve's key) from a strided sample; with alpha, of the covered
    # pixels' straight colour, each counted by its coverage (lenslab.tone.exposure)
    ev = parse_exposure(exposure, x, primaries, alpha)
    scale = 2.0 ** ev
    # luminance weights only where something weighs channels (importing colour-science takes a while)
    needs_weights = rgb and (mode_key == "luminance" or spec.kind == "image")
    weights = luminance_weights(primaries) if needs_weights else None
    if spec.kind == "image":
        # Reinhard et al. 2002: the scale key / log-average comes from the image's luminance
        lum, coverage = covered_luminance(x, weights) if alpha else (luminance_sample(x, weights, alpha=False), None)
        lum *= scale
        avg = log_average(lum, delta=resolved["delta"], weights=coverage) if lum.size else 1.0
        scale = scale * resolved["key"] / max(avg, 1e-30)
    # the result in x's memory: the caller gave it up, and each block is read before it is written (per
    # value, or RGB through planar copies; an image with alpha maps a copy of its straight colour)
    same = _own(image, x, in_place) and x.flags.c_contiguous and (alpha or mode_key == "per-channel" or not rgb)
    out = x if same else np.empty_like(x)
    counts, is_slight = Counts(), True
    # bands where something is copied or judged before its memory is overwritten: the straight colour of an
    # image with alpha, or an image mapped in place that holds negatives beyond the slight ones; else one pass
    clean = None if alpha or not same else bool(x.min() >= -SLIGHT)
    spans = _bands(x) if alpha or clean is False else [(0, x.shape[0])]
    with np.errstate(divide="ignore", over="ignore"):
        for r0, r1 in spans:
            is_slight &= _band(spec, resolved, scale, x[r0:r1], out[r0:r1], same, alpha, rgb, mode_key, weights,
                               counts, threads, clean)
    warn_repairs(counts, x.size - (x[..., -1].size if alpha else 0), is_slight=is_slight)
    return out


#: values of one band of rows (a band, its straight colour and a mapped copy stay a few MB)
BAND_VALUES = 1 << 21


def _bands(x: np.ndarray) -> list[tuple[int, int]]:
    """Bands of the rows of ``x``: a multiple of 8 rows each (the 8 x 8 blocks of :func:`slight`) of about
    :data:`BAND_VALUES` values; a 1-D array is one band."""
    n = x.shape[0] if x.ndim else 0
    if x.ndim < 2 or n == 0:
        return [(0, n)] if n else []
    per_row = max(1, x[0].size)
    rows = max(8, BAND_VALUES // per_row // 8 * 8)
    return [(r, min(n, r + rows)) for r in range(0, n, rows)]


def _band(spec, resolved, scale, xb, ob, same, alpha, rgb, mode_key, weights, counts, threads, clean=None) -> bool:
    """Map the band ``xb`` into ``ob`` (``same``: the same memory), counting the repairs into ``counts``;
    whether its negatives are all slight (:func:`slight`). With ``alpha`` (the last channel, colour
    premultiplied): the curve acts on the straight colour, which is premultiplied again, and alpha is
    clipped to [0, 1]. ``clean``: whether the band holds no negative beyond the slight ones, when known."""
    if alpha:
        a = np.clip(np.nan_to_num(xb[..., -1], nan=0.0, posinf=1.0, neginf=0.0), 0, 1)[..., None]
        src = xb[..., :-1].copy()
        np.divide(src, a, out=src, where=a > 0)
    else:
        src = xb
    # in place where each block is read before it is written (per value, or RGB through planar copies) and
    # the band's input is not needed again (no negative beyond the slight ones to judge)
    writable = (alpha or same) and (mode_key == "per-channel" or not rgb)
    if writable and (clean if clean is not None else bool(src.min() >= -SLIGHT)):
        dst = src
    else:
        dst = np.empty_like(src) if alpha or same else ob
    tally = Counts()
    _apply_global(spec, resolved, scale, src, dst, rgb, mode_key, weights, tally, threads)
    # judged before the band's memory takes the result
    judged = not tally.negative or bool(tally.nan or tally.posinf) or slight(src, tally.lowest)
    if alpha:
        dst *= a
        ob[..., :-1] = dst
        ob[..., -1:] = a
    elif dst is not ob:
        ob[...] = dst
    counts.add(tally)
    return judged


def _local(image, x, spec, resolved, exposure, mode_key, primaries, threads, in_place, alpha) -> np.ndarray:
    """A local curve (it looks at the whole image): on a copy of the straight colour."""
    if alpha:
        a = np.clip(np.nan_to_num(x[..., -1], nan=0.0, posinf=1.0, neginf=0.0), 0, 1)
        colour_part = x[..., :-1].copy()
        np.divide(colour_part, a[..., None], out=colour_part, where=a[..., None] > 0)
        ev = parse_exposure(exposure, x, primaries, True)  # the covered pixels' (lenslab.tone.exposure)
        mapped = tonemap(colour_part, spec.name, ev, mode_key, primaries=primaries, threads=threads,
                         in_place=True, alpha_channel=False, **resolved)  # (the copy is this function's own)
        del colour_part
        mapped *= a[..., None]
        out = x if _own(image, x, in_place) else np.empty(x.shape, F32)
        out[..., :-1] = mapped
        out[..., -1] = a
        return out
    rgb = x.ndim == 3 and x.shape[-1] == 3
    ev = parse_exposure(exposure, x, primaries, False)
    if spec.ignores_exposure and ev != 0:
        warnings.warn(ExposureIgnoredWarning(f"the exposure has no effect with tone curve {spec.name}: "
                                             f"{spec.ignores_exposure}"), stacklevel=3)
    counts = Counts()
    clean = x.copy()
    inf_mask = repair(clean, counts)
    clean *= F32(2.0 ** ev)
    out = spec.build(clean, resolved, luminance_weights(primaries))
    out[inf_mask.any(axis=-1) if rgb else inf_mask] = 1
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

