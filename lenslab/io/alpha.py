"""Alpha: one meaning in memory, each format's own rule in files.

In memory an image carries alpha last where its channel names say so (only ``A`` is alpha); an array
without names, when it has 2 or 4 channels (Y A, R G B A): :func:`alpha_last` is that one rule; alpha is *coverage* in
[0, 1] and the colour is *premultiplied* by it (the OpenEXR convention): a pixel half covered by a
surface of straight colour ``c`` holds ``(c / 2, 1 / 2)``. :func:`settle` is where that holds after
every operation (the warp engine calls it on every output, whatever filter, falloff, per-channel
lens or blend made it); the format plugins call :func:`premultiply` and :func:`unpremultiply` at the
file boundary for formats that store straight colour (PNG, integer TIFF tagged unassociated), so
memory always holds premultiplied colour.

Rules of :func:`settle`, per pixel, for alpha ``a``:

- ``a > 1`` (a filter's overshoot): alpha becomes 1 and the colour is divided by ``a``, so the
  straight colour ``colour / a`` a compositor recovers is kept;
- ``a < 0`` (a negative lobe outside a matte) or NaN: alpha and colour become 0 (there is nothing
  covered to have a colour);
- ``0 <= a <= 1``: untouched (colour with ``a = 0`` stays: premultiplied colour may add light where
  nothing covers, as a flare or glow layer does).

Operations that change light but not coverage (vignetting and its removal, exposure) act on the
colour channels only; :func:`colour_channels` says which those are.
"""

from __future__ import annotations

import numpy as np

F32 = np.float32


def alpha_last(nc: int, alpha: bool | None = None) -> bool:
    """The one rule of which images carry alpha: an image of ``nc`` channels carries it last when ``alpha``
    says so (what its channel names say, :func:`lenslab.io.carries_alpha`: only ``A`` is alpha, so ``u, v``
    or ``R, G, B, Z`` carry none) and it has a channel besides; with nothing said (``alpha=None``: an array
    without names), when ``nc`` is 2 or 4 (``Y A``, ``R G B A``).

    >>> alpha_last(4), alpha_last(4, False), alpha_last(2, True), alpha_last(3), alpha_last(1, True)
    (True, False, True, False, False)
    """
    if alpha is not None:
        return bool(alpha) and nc >= 2
    return nc in (2, 4)


def has_alpha(image: np.ndarray, alpha: bool | None = None) -> bool:
    """Whether an H x W x C image carries alpha (:func:`alpha_last`)."""
    return image.ndim == 3 and alpha_last(image.shape[2], alpha)


def colour_channels(nc: int, alpha: bool | None = None) -> slice:
    """The channels of an image with ``nc`` channels that hold light or data (all but a trailing alpha,
    :func:`alpha_last`)."""
    return slice(0, nc - 1) if alpha_last(nc, alpha) else slice(0, nc)


def settle(image: np.ndarray, coverage: np.ndarray | None = None, alpha: bool | None = None) -> None:
    """Hold the contract in place: ``image`` (H x W x C float32, colour premultiplied) and ``coverage``
    (H x W float32, the warp's fraction of valid samples) end with every alpha in [0, 1].

    ``coverage`` is clipped to [0, 1] (NaN to 0); an image with alpha (C = 2 or 4) has its alpha and
    colour settled by the rules of the module docstring; ``alpha=False``: the image holds data channels
    only (none is clipped or used as coverage)."""
    # two reductions find the usual case (nothing to do) at a fraction of the cost of fixing; a NaN makes
    # the test fail and is fixed with the rest
    if coverage is not None and coverage.size and not (coverage.min() >= 0.0 and coverage.max() <= 1.0):
        np.nan_to_num(coverage, copy=False, nan=0.0)
        np.clip(coverage, 0.0, 1.0, out=coverage)
    if image.ndim != 3 or not has_alpha(image, alpha) or not image.size:
        return
    a = image[..., -1]
    if a.min() >= 0.0 and a.max() <= 1.0:
        return
    over = a > 1.0
    under = ~(a >= 0.0)  # negative or NaN
    if over.any():
        scale = np.ones_like(a)
        np.divide(1.0, a, out=scale, where=over)
        image[..., :-1] *= scale[..., None]
        a[over] = 1.0
    if under.any():
        image[under] = 0.0


def unpremultiply(image: np.ndarray, alpha: bool | None = None) -> np.ndarray:
    """Premultiplied (memory) -> straight colour (PNG, integer TIFF): a float32 copy, colour divided by
    alpha where alpha > 0 and 0 where alpha is 0; alpha clipped to [0, 1]. Images without alpha are
    returned as they are (``alpha``: :func:`alpha_last`)."""
    if not has_alpha(image, alpha):
        return image
    out = np.array(image, dtype=F32, copy=True)
    a = np.clip(np.nan_to_num(out[..., -1:], nan=0.0), 0.0, 1.0)
    colour = out[..., :-1]
    np.divide(colour, a, out=colour, where=a > 0)
    colour[np.broadcast_to(a <= 0, colour.shape)] = 0.0
    out[..., -1:] = a
    return out


def premultiply(image: np.ndarray, alpha: bool | None = None) -> np.ndarray:
    """Straight colour (as PNG and unassociated TIFF store it) -> premultiplied, in place; returned."""
    if has_alpha(image, alpha):
        image[..., :-1] *= image[..., -1:]
    return image


def expose(image: np.ndarray, stops: float, in_place: bool = False, alpha: bool | None = None) -> np.ndarray:
    """``image`` (H x W x C float32) with its colour times ``2**stops`` and alpha kept (exposure is light,
    not coverage); a new array, or with ``in_place`` ``image`` itself when it is float32 (the caller gives
    it up: no copy of the image's size)."""
    own = in_place and isinstance(image, np.ndarray) and image.dtype == F32 and image.flags.writeable
    out = image if own else np.array(image, dtype=F32, copy=True)
    if float(stops) != 0.0:
        out[..., colour_channels(out.shape[-1], alpha) if out.ndim == 3 else slice(None)] *= F32(2.0 ** float(stops))
    return out


def split_alpha(out: np.ndarray, coverage: np.ndarray, alpha: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A warp's ``(image, coverage)`` -> ``(premultiplied colour, alpha)``: an image that carries alpha
    (``alpha``, else by its channel count: :func:`has_alpha`) gives its own (warped like colour, so it
    includes the coverage), any other the coverage."""
    if has_alpha(out, alpha):
        return out[..., :-1], out[..., -1]
    return out, coverage


def with_alpha(colour: np.ndarray, alpha: np.ndarray, channels: tuple[int, ...]) -> np.ndarray:
    """``colour`` (H x W x C, premultiplied) with ``alpha`` (H x W) appended, fitted to a format that holds
    ``channels`` channel counts: grey + alpha becomes RGB + alpha where the format holds no 2-channel
    image (PNG)."""
    if colour.shape[2] + 1 not in channels and colour.shape[2] == 1:
        colour = np.repeat(colour, 3, axis=2)
    return np.concatenate([colour, alpha[..., None].astype(F32, copy=False)], axis=-1)



def room_for_alpha(h: int, w: int, c: int) -> tuple[np.ndarray, np.ndarray]:
    """``(colour, alpha)`` arrays for a warp's output of ``h x w x c`` that are the channels of one
    ``h x w x (c + 1)`` image (strided views: the engine draws each band in scratch memory and copies it in),
    which :func:`joined_alpha` gives back without a copy."""
    image = np.empty((h, w, c + 1), F32)
    return image[..., :c], image[..., c]


def joined_alpha(colour: np.ndarray, alpha: np.ndarray) -> np.ndarray | None:
    """``colour`` (H x W x C) and ``alpha`` (H x W) as one H x W x (C + 1) image (premultiplied colour, alpha
    last) without a copy when they are the channels of one such image (:func:`room_for_alpha`, or a warp of a
    source that carries alpha); None otherwise (they are not)."""
    h, w, c = colour.shape
    pixel = 4 * (c + 1)
    if alpha.shape != (h, w) or colour.dtype != F32 or alpha.dtype != F32 or colour.base is None:
        return None
    if colour.strides == alpha.strides + (4,) == (w * pixel, pixel, 4) and np.shares_memory(alpha, colour.base) \
            and alpha.ctypes.data == colour.ctypes.data + 4 * c:
        return np.lib.stride_tricks.as_strided(colour, (h, w, c + 1), colour.strides)
    return None
