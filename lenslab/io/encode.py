"""Display encoding: the sRGB transfer function (:mod:`lenslab.srgb`) and integer quantisation.

LDR files (PPM/PGM, JPG, PNG) hold sRGB-encoded code values. Reading decodes them to linear light;
writing encodes linear light in [0, 1] and quantises with round-to-nearest (optionally dithered).

Speed without hand-writing the curve: decoding goes through a table of every code value
(:func:`lenslab.srgb.decode_table`). Encoding to 8 or 16 bits goes through a table of the decision
thresholds (the linear values where the rounded code steps up, :func:`lenslab.srgb.thresholds`): the
result is exactly ``round(maxval * eotf_inverse_sRGB(x))`` at table-lookup speed. Those tables are
colour-science's function, built once and cached on disk, so a command that writes one small file
does not wait for colour-science to import.
"""

from __future__ import annotations

import functools

import numpy as np

from lenslab import srgb


def decode_srgb(codes: np.ndarray, maxval: int) -> np.ndarray:
    """Integer code values (0..maxval) -> linear light, float32."""
    return srgb.decode_table(int(maxval))[codes]


def encode_srgb(linear: np.ndarray) -> np.ndarray:
    """Linear light -> sRGB-encoded value (float32, the same shape); inputs are clipped to [0, 1] first."""
    return srgb.encode(linear)


#: table cells per bit depth, finer than the narrowest code step (near black, on the linear segment:
#: 1 / (255 * 12.92) = 3.0e-4 for 8 bits, 1.2e-6 for 16), so at most one threshold falls in a cell
_CELLS = {8: 1 << 14, 16: 1 << 20}


@functools.lru_cache(maxsize=2)
def _encode_tables(bits: int) -> tuple[np.ndarray, np.ndarray]:
    """(code at each cell's lower edge, the next threshold above it) for exact table encoding."""
    maxval = (1 << bits) - 1
    cells = _CELLS[bits]
    # linear value at which the rounded code reaches k (k = 1..maxval), from the sRGB EOTF
    thr64 = srgb.thresholds(bits)
    # the smallest float32 not below each threshold, so that float32 comparisons round as float64 would
    thr = thr64.astype(np.float32)
    below = thr.astype(np.float64) < thr64
    thr[below] = np.nextafter(thr[below], np.float32(np.inf))
    edges = (np.arange(cells + 1, dtype=np.float64) / cells).astype(np.float32)
    low = np.searchsorted(thr, edges, side="right").astype(np.uint8 if bits == 8 else np.uint16)
    # the next threshold above each cell; NaN past the last, so that nothing passes maxval
    nxt = np.append(thr, np.float32(np.nan))[low]
    return low, nxt.astype(np.float32)


def _clean(linear: np.ndarray) -> np.ndarray:
    x = np.asarray(linear, dtype=np.float32)
    x = np.nan_to_num(x, nan=0.0, posinf=1.0, neginf=0.0)
    return np.clip(x, 0.0, 1.0, out=x)  # nan_to_num made a copy: clipping in place is safe


def quantise(values: np.ndarray, bits: int, dither: bool = False, seed: int | None = 0) -> np.ndarray:
    """Values in [0, 1] (already display-encoded, or raw codes/maxval) -> uint8 or uint16 codes.

    Rounds to nearest. ``dither=True`` adds triangular (TPDF) noise of +-1 code before rounding, which
    trades banding in smooth gradients for fine grain.
    """
    rng = np.random.default_rng(seed) if dither else None
    return _quantise(values, bits, (rng, rng) if dither else None)


def _quantise(values: np.ndarray, bits: int, noise=None) -> np.ndarray:
    """:func:`quantise` with the dither's two uniform draws taken from the generators ``noise`` (None: no
    dither): the same pair twice for a whole image, or two streams apart by the image's size for a block."""
    maxval = (1 << bits) - 1
    x = _clean(values) * np.float32(maxval)
    if noise is not None:
        x += (noise[0].random(x.shape, dtype=np.float32) - noise[1].random(x.shape, dtype=np.float32))
    x = np.floor(x + np.float32(0.5), out=x)
    np.clip(x, 0, maxval, out=x)
    return x.astype(np.uint8 if bits <= 8 else np.uint16)


def encode_quantise(linear: np.ndarray, bits: int = 8, dither: bool = False, seed: int | None = 0) -> np.ndarray:
    """Linear light -> sRGB code values (uint8 for 8 bits, uint16 for 16 bits), rounded to nearest.

    NaN becomes 0, values are clipped to [0, 1]. Without dither this is a table lookup that gives
    exactly the rounded colour-science encoding.
    """
    if bits in _CELLS and not dither:
        return _encode_table(np.asarray(linear, dtype=np.float32), bits)
    return quantise(encode_srgb(linear), bits, dither=dither, seed=seed)


_BLOCK = 1 << 16  # values per block: the block and its scratch buffers stay in a core's L2 cache


def _encode_table(x: np.ndarray, bits: int) -> np.ndarray:
    """Exact 8- or 16-bit sRGB encoding by table lookup, in cache-sized blocks (one sweep through memory).

    Per value: ``i = floor(clip(x * FINE))`` picks a table cell; the cell's lower-edge code, plus one
    if ``x`` reaches the single threshold that may fall inside the cell. ``fmax``/``fmin`` send NaN
    and -inf to cell 0 and +inf to the last cell; the threshold test is False for NaN.
    """
    low, nxt = _encode_tables(bits)
    flat = np.ascontiguousarray(x).reshape(-1)
    out = np.empty(flat.shape, low.dtype)
    n = flat.size
    bs = min(_BLOCK, max(n, 1))
    y = np.empty(bs, np.float32)
    i = np.empty(bs, np.intp)
    t = np.empty(bs, np.float32)
    hit = np.empty(bs, np.bool_)
    fine = np.float32(_CELLS[bits])
    for s in range(0, n, bs):
        e = min(s + bs, n)
        m = e - s
        xb, yb, ib, tb, hb = flat[s:e], y[:m], i[:m], t[:m], hit[:m]
        np.multiply(xb, fine, out=yb)
        np.fmax(yb, 0, out=yb)
        np.fmin(yb, fine, out=yb)
        ib[...] = yb  # truncation = floor for these non-negative values
        ob = out[s:e]
        np.take(low, ib, out=ob)
        np.take(nxt, ib, out=tb)
        np.greater_equal(xb, tb, out=hb)
        ob += hb
    return out.reshape(x.shape)


def decode_codes(codes: np.ndarray, maxval: int, raw: bool = False) -> np.ndarray:
    """Integer samples H x W x C of an LDR file -> float32: colour sRGB-decoded to linear light (``raw``:
    code / maxval), and alpha (the last channel of 2 or 4) always code / maxval, since it is coverage."""
    if raw:
        return codes.astype(np.float32) / np.float32(maxval)
    image = decode_srgb(codes, maxval)
    if codes.shape[-1] in (2, 4):
        image[..., -1] = codes[..., -1].astype(np.float32) / np.float32(maxval)
    return image


class NonFiniteWarning(UserWarning):
    """A writer replaced NaN or infinite samples (the format cannot hold them); the message counts them."""


def count_non_finite(image: np.ndarray, rows: int = 256) -> tuple[int, int, int]:
    """(NaN, +inf, -inf) sample counts of an array, a block of rows at a time (no full-size mask)."""
    nan = pos = neg = 0
    a = image.reshape(image.shape[0], -1) if image.ndim > 1 else image.reshape(1, -1)
    for y in range(0, a.shape[0], rows):
        block = a[y:y + rows]
        if np.isfinite(block.sum(dtype=np.float64)):  # the common case: one pass, no mask
            continue
        nan += int(np.count_nonzero(np.isnan(block)))
        pos += int(np.count_nonzero(block == np.inf))
        neg += int(np.count_nonzero(block == -np.inf))
    return nan, pos, neg


def note_non_finite(image: np.ndarray | None, title: str, becomes: str, counts: tuple[int, int, int] | None = None,
                    stacklevel: int = 3) -> None:
    """Warn (:class:`NonFiniteWarning`) with the counts of NaN and infinite samples ``title`` replaces:
    those of ``image``, or ``counts`` (NaN, +inf, -inf) already made."""
    import warnings

    nan, pos, neg = count_non_finite(image) if counts is None else counts
    if nan or pos or neg:
        parts = [f"{n} {what}" for n, what in ((nan, "NaN"), (pos, "+inf"), (neg, "-inf")) if n]
        warnings.warn(NonFiniteWarning(f"{title} cannot hold NaN or infinity: {', '.join(parts)} sample(s) written "
                                       f"as {becomes}"), stacklevel=stacklevel)


def _noise_streams(values: int, seed: int = 0):
    """Two generators that give, block after block, the two uniform draws :func:`quantise` takes for an
    array of ``values`` values: the second starts where the first draw of the whole array ends."""
    first, second = np.random.default_rng(seed), np.random.default_rng(seed)
    for s in range(0, values, _BLOCK):  # (drawn and dropped: the float32 draws of a generator are a stream)
        second.random(min(_BLOCK, values - s), dtype=np.float32)
    return first, second


def encode_codes(image: np.ndarray, bits: int, raw: bool = False, dither: bool = False,
                 straight: bool = False, in_place: bool = False) -> np.ndarray:
    """Float32 H x W x C -> uint8/uint16 samples: colour sRGB-encoded (``raw``: value * maxval), alpha
    (the last channel of 2 or 4) always value * maxval; rounded to nearest (``dither``: TPDF, as
    :func:`quantise` with seed 0). NaN and infinite samples (NaN and -inf as 0, +inf as maxval) are
    counted in a :class:`NonFiniteWarning`. ``straight`` (not with ``raw``): ``image`` holds
    premultiplied colour and the samples are of straight colour, as ``unpremultiply(image)`` gives.

    Works a block of pixels at a time into the output: no float copy of the image's size (the codes
    are those of the whole image at once, dither included). ``in_place``: the codes are written into the
    first bytes of ``image``'s own memory (a C-contiguous, writable float32 array the caller gives up: it
    is overwritten), so the only memory of the image's size is the image itself."""
    from lenslab.io.alpha import unpremultiply

    c = image.shape[-1]
    alpha = c in (2, 4) and not raw
    coded = c - 1 if alpha else c  # channels encoded (and dithered); alpha is quantised alone
    pixels = image.reshape(-1, c)
    n = pixels.shape[0]
    kind = np.uint8 if bits <= 8 else np.uint16
    own = (in_place and image.dtype == np.float32 and image.flags.c_contiguous and image.flags.writeable
           and image.size > 0)
    # in place: block i's codes land at bytes a quarter (8 bits) or a half (16 bits) of the way to its own
    # floats, over floats of this block or earlier ones, which are read into the block's codes before
    out = pixels.reshape(-1).view(kind)[:n * c].reshape(n, c) if own else np.empty((n, c), kind)
    noise = _noise_streams(n * coded) if dither else None
    nan = pos = neg = 0
    step = max(1, _BLOCK // c)
    codes = np.empty((min(step, n), c), kind)
    for s in range(0, n, step):
        block = pixels[s:s + step]
        m = block.shape[0]
        if straight and alpha:
            block = unpremultiply(block[None])[0]
        counts = count_non_finite(block)
        nan, pos, neg = nan + counts[0], pos + counts[1], neg + counts[2]
        colour = block[:, :coded]
        if raw:
            codes[:m, :coded] = _quantise(colour, bits, noise)
        elif noise is None and bits in _CELLS:
            codes[:m, :coded] = _encode_table(colour.astype(np.float32, copy=False), bits)
        else:
            codes[:m, :coded] = _quantise(encode_srgb(colour), bits, noise)
        if alpha:
            codes[:m, coded:] = quantise(block[:, coded:], bits)
        out[s:s + m] = codes[:m]
    note_non_finite(None, f"{bits}-bit integer samples", "0 (NaN, -inf) and the largest code (+inf)",
                    counts=(nan, pos, neg))
    return out.reshape(image.shape)
