"""Y'CbCr frames <-> linear light in one compiled pass each way (``src/native/video_ycbcr.cpp``), exact to the matrix
and range formulas of ITU-R BT.709, BT.601 and BT.2020 (non-constant luminance) as ITU-T H.273 states them:

- limited range, n bits: ``Y = round((219 E'y + 16) 2^(n-8))``, ``C = round((224 E'c + 128) 2^(n-8))``;
- full range: ``Y = round((2^n - 1) E'y)``, ``C = round((2^n - 1) E'c + 2^(n-1))``;
- ``E'y = Kr R' + (1 - Kr - Kb) G' + Kb B'``, ``E'cb = (B' - E'y) / (2 (1 - Kb))``, ``E'cr = (R' - E'y) / (2 (1 - Kr))``.

Decoding takes the decoder's planes as they are (no copy, no swscale): chroma is repeated over its block (as
swscale's default does), R'G'B' is computed in float32, clamped to [0, 1] and taken through the transfer function's
65536-entry table (:func:`lenslab.io.video.colour.decode_table`) interpolated linearly, then BT.2020 -> Rec.709
where the stream is wide (float32 throughout: within a few float32 steps of the exact values); for 8-bit samples R'
and B' (which need no Cb, no Cr respectively) come from 256 x 256 tables of the same lookups (:func:`_rb_tables`).
Only the window a warp reads is computed. Encoding takes linear light through the
inverse transfer function's table (:func:`lenslab.io.video.colour.encode_table`) to R'G'B' in [0, 1], then to
codes rounded once at the stream's depth; a chroma sample is the mean of its block's Cb (Cr).

swscale's 16-bit RGB paths, which these replace, are not exact: they decode a 10-bit white (Y' = 940) to
65283/65535 and encode 1.0 to Y' = 943. :func:`ycbcr_to_linear_reference` and :func:`linear_to_ycbcr_reference`
are the NumPy references the tests compare the compiled passes with. Formats or matrices outside
``FORMATS`` / ``MATRICES`` (and HLG, whose EOTF mixes the channels) keep swscale's path.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from lenslab.io.colour.primaries import H273_YCBCR, ycbcr_weights
from lenslab.io.video.colour import (KNOT_SHIFT, LOW, decode_table, encode_table, is_wide, matrix_from_709,
                                     matrix_to_709,
                                     threads)

#: planar pixel formats: (bits, log2 chroma subsampling across, down)
FORMATS = {"yuv420p": (8, 1, 1), "yuv422p": (8, 1, 0), "yuv444p": (8, 0, 0),
           "yuv420p10le": (10, 1, 1), "yuv422p10le": (10, 1, 0), "yuv444p10le": (10, 0, 0),
           "yuv420p12le": (12, 1, 1), "yuv422p12le": (12, 1, 0), "yuv444p12le": (12, 0, 0)}
#: matrix tags (H.273) these passes take, with colour-science's (Kr, Kb) (:func:`lenslab.io.colour.primaries.ycbcr_weights`)
MATRICES = frozenset(H273_YCBCR)


def exact(info, pix_fmt: str) -> bool:
    """Whether frames of ``pix_fmt`` in a stream like ``info`` go through these passes."""
    return pix_fmt in FORMATS and info.matrix in MATRICES and info.curve != "hlg" and not info.rgb


def rgb_to_ycbcr_matrix(matrix: int) -> np.ndarray:
    """R'G'B' -> (E'y, E'cb, E'cr), 3 x 3 float64."""
    kr, kb = ycbcr_weights(matrix)
    kg = 1.0 - kr - kb
    return np.array([[kr, kg, kb],
                     [-kr / (2 * (1 - kb)), -kg / (2 * (1 - kb)), 0.5],
                     [0.5, -kg / (2 * (1 - kr)), -kb / (2 * (1 - kr))]])


def ycbcr_to_rgb_matrix(matrix: int) -> np.ndarray:
    """(E'y, E'cb, E'cr) -> R'G'B', 3 x 3 float64: the inverse of :func:`rgb_to_ycbcr_matrix`, its first column 1."""
    kr, kb = ycbcr_weights(matrix)
    kg = 1.0 - kr - kb
    return np.array([[1.0, 0.0, 2 * (1 - kr)],
                     [1.0, -2 * kb * (1 - kb) / kg, -2 * kr * (1 - kr) / kg],
                     [1.0, 2 * (1 - kb), 0.0]])


def code_range(bits: int, full: bool) -> np.ndarray:
    """``(y0, ys, c0, cs)``: ``E'y = (Y - y0) / ys``, ``E'c = (C - c0) / cs`` for codes of ``bits`` bits."""
    if full:
        top = float((1 << bits) - 1)
        return np.array([0.0, top, float(1 << (bits - 1)), top])
    s = float(1 << (bits - 8))
    return np.array([16.0 * s, 219.0 * s, 128.0 * s, 224.0 * s])


def planes(frame) -> list[np.ndarray]:
    """The Y, Cb and Cr planes of a PyAV frame as 2-D arrays over its own buffers (rows padded to the line size)."""
    dtype = np.uint8 if FORMATS[frame.format.name][0] == 8 else np.uint16
    size = np.dtype(dtype).itemsize
    return [np.frombuffer(p, dtype).reshape(p.height, p.line_size // size) for p in frame.planes[:3]]


@lru_cache(maxsize=8)
def _pairs(curve: str, wide: bool) -> np.ndarray:
    """The decoding table as 65536 float32 pairs (value at code i, step to code i + 1; the last step 0)."""
    t = np.asarray(decode_table(curve, wide), np.float64).reshape(-1)
    return np.ascontiguousarray(np.stack([t, np.append(np.diff(t), 0.0)], -1), np.float32).reshape(-1)


@lru_cache(maxsize=8)
def _rb_tables(curve: str, wide: bool, full: bool, matrix: int) -> np.ndarray:
    """8-bit samples: the linear R' by (Cr, Y') and B' by (Cb, Y'), 2 x 256 x 256 float32, made by the lookups the
    compiled decoding makes (R' has no Cb term and B' no Cr in these matrices), so that it looks up G' alone."""
    from lenslab.native import extension

    out = np.empty(2 * 65536, np.float32)
    extension().ycbcr_rb_tables(code_range(8, full), ycbcr_to_rgb_matrix(matrix), _pairs(curve, wide), out)
    return out


def _decode_args(info, pix_fmt: str):
    bits, hx, vy = FORMATS[pix_fmt]
    wide = is_wide(info.primaries)
    prim = np.ascontiguousarray(matrix_to_709(info.primaries)) if wide else np.empty(0)
    return (hx, vy, code_range(bits, info.range == 2), ycbcr_to_rgb_matrix(info.matrix),
            _pairs(info.curve, wide), prim)


def ycbcr_to_linear(frame, info, window=None, out: np.ndarray | None = None) -> np.ndarray:
    """A decoded PyAV frame (a format of ``FORMATS``) -> linear Rec.709 float32 H x W x 3, in one compiled pass.

    ``window`` ``(row0, row1, col0, col1)``, or each row's two spans of columns (``H x 4`` int64, start and end of each;
    :func:`lenslab.warp.taps.source_spans`): only those pixels are written (into ``out`` when given, reused from
    frame to frame; else into a new frame of zeros)."""
    h, w = frame.height, frame.width
    if out is None:
        out = (np.empty if window is None else np.zeros)((h, w, 3), np.float32)
    spans = np.empty(0, np.int64)
    if isinstance(window, np.ndarray):
        spans, window = np.ascontiguousarray(window, np.int64).reshape(-1), None
    r0, r1, c0, c1 = window or (0, h, 0, w)
    y, u, v = planes(frame)
    hx, vy, rng, k, table, prim = _decode_args(info, frame.format.name)
    rb = _rb_tables(info.curve, is_wide(info.primaries), info.range == 2, info.matrix) if y.dtype == np.uint8 \
        else np.empty(0, np.float32)
    from lenslab.native import extension

    extension().ycbcr_to_linear(y, u, v, hx, vy, rng, k, table, rb, prim, out, r0, r1, c0, c1, spans, threads())
    return out


def ycbcr_to_linear_reference(y, u, v, info, pix_fmt: str, size: tuple[int, int]) -> np.ndarray:
    """NumPy reference of :func:`ycbcr_to_linear`: planes (2-D arrays) -> linear float32 ``size`` (H, W) x 3."""
    h, w = size
    hx, vy, (y0, ys, c0, cs), k, table, prim = _decode_args(info, pix_fmt)

    def up(c):
        return np.repeat(np.repeat(c, 1 << vy, 0), 1 << hx, 1)[:h, :w]

    f32 = np.float32
    n = np.arange(256 if y.dtype == np.uint8 else 65536, dtype=np.float64)
    ly, lc = ((n - y0) / ys * 65535.0).astype(f32), ((n - c0) / cs * 65535.0).astype(f32)
    cb, cr = lc[up(u)], lc[up(v)]
    x = ly[y[:h, :w]][..., None] + (k[:, 1].astype(f32) * cb[..., None] + k[:, 2].astype(f32) * cr[..., None])
    x = np.clip(x, 0.0, 65535.0).astype(f32)
    i = x.astype(np.int32)  # at most 65535, whose step is 0
    lin = table[2 * i] + (x - i.astype(f32)) * table[2 * i + 1]
    return lin @ prim.T.astype(f32) if prim.size else lin


def _encode_args(info, pix_fmt: str, encoded: bool):
    bits, hx, vy = FORMATS[pix_fmt]
    empty = np.empty(0)
    if encoded:  # code values already: a clamp
        curve, zero, prim = np.empty(0, np.float32), 0.0, empty
    else:
        curve, zero = encode_table(info.curve)
        prim = matrix_from_709(info.primaries) if is_wide(info.primaries) else empty
    b0 = int(np.array(2.0**LOW, np.float32).view(np.uint32))
    return (bits, hx, vy, np.ascontiguousarray(prim), np.ascontiguousarray(curve, np.float32), b0, float(zero),
            rgb_to_ycbcr_matrix(info.matrix), code_range(bits, info.range == 2), float((1 << bits) - 1))


def linear_to_ycbcr(image: np.ndarray, info, pix_fmt: str, encoded: bool = False, reuse=None):
    """Linear Rec.709 float32 H x W x 3 (``encoded``: code values in [0, 1] in the stream's primaries and transfer)
    -> a PyAV frame of ``pix_fmt`` (a format of ``FORMATS``) with the stream's matrix and range, in one compiled
    pass; NaN and infinities as :func:`lenslab.io.video.colour.from_linear` makes them finite.

    ``reuse``: an earlier frame to write into when it has this size and format. An encoder that still holds it
    makes PyAV give it new memory first (``make_writable``); one that is done with it leaves its pages, so a 4K
    frame's 5.5 MB is not faulted in anew every frame."""
    image = np.ascontiguousarray(image[..., :3], np.float32)
    h, w = image.shape[:2]
    rows = RowsToYCbCr(info, pix_fmt, encoded, ycbcr_frame(w, h, pix_fmt, reuse))
    rows(image, slice(0, h))
    return rows.frame


def ycbcr_frame(w: int, h: int, pix_fmt: str, reuse=None):
    """A PyAV frame of ``pix_fmt`` to write: ``reuse`` (made writable) when it has this size and format."""
    import av

    if reuse is not None and (reuse.width, reuse.height, reuse.format.name) == (w, h, pix_fmt):
        reuse.make_writable()
        return reuse
    return av.VideoFrame(w, h, pix_fmt)


class RowsToYCbCr:
    """:func:`linear_to_ycbcr` a few rows at a time, into ``frame``'s planes: called as ``(rows, sl)`` with the
    rows ``sl`` of a linear frame (a warp's ``on_band``, on each band's thread while its rows are in cache), and
    :meth:`finish`-ed with the whole frame. The rows of a chroma block that two calls share (4:2:0) are left to
    :meth:`finish`, so every code is what one pass over the frame gives."""

    def __init__(self, info, pix_fmt: str, encoded: bool, frame):
        self.args = _encode_args(info, pix_fmt, encoded)
        self.frame, self.planes, self.height = frame, planes(frame), frame.height
        self.block = 1 << self.args[2]
        self.shared: set[int] = set()

    def __call__(self, rows: np.ndarray, sl: slice) -> None:
        r0, r1, b = sl.start, sl.stop, self.block
        a, z = -(-r0 // b) * b, (r1 if r1 == self.height else r1 // b * b)  # whole blocks: rows a to z
        if r0 < a:
            self.shared.add(a - b)
        if z < r1:
            self.shared.add(z)
        if a < z:
            self._convert(rows[a - r0:z - r0], a, z, threads() if z - a == self.height else 1)

    def _convert(self, rows: np.ndarray, a: int, z: int, n: int) -> None:
        from lenslab.native import extension

        bits, hx, vy, prim, curve, b0, zero, k, rng, top = self.args
        y, u, v = self.planes
        c0, c1 = a >> vy, (z + (1 << vy) - 1) >> vy
        extension().linear_to_ycbcr(np.ascontiguousarray(rows[..., :3], np.float32), prim, curve, b0, KNOT_SHIFT, zero,
                                    k, rng, top, y[a:z], u[c0:c1], v[c0:c1], hx, vy, n)

    def finish(self, image: np.ndarray):
        """The frame, once every row of ``image`` (the linear frame) has been given: the shared blocks converted."""
        for a in sorted(self.shared):
            z = min(self.height, a + self.block)
            self._convert(image[a:z], a, z, 1)
        self.shared.clear()
        return self.frame


def linear_to_ycbcr_reference(image: np.ndarray, info, pix_fmt: str) -> list[np.ndarray]:
    """NumPy reference of :func:`linear_to_ycbcr` (linear light), with colour-science's inverse transfer function
    in float64 in place of its table: the Y, Cb and Cr planes as integer arrays (H x W, then the chroma size)."""
    from lenslab.io.video.colour import from_linear

    bits, hx, vy, _, _, _, _, k, (y0, ys, c0, cs), top = _encode_args(info, pix_fmt, True)
    e = np.clip(from_linear(image[..., :3], info), 0.0, 1.0) @ k.T
    h, w = e.shape[:2]
    bh, bw = 1 << vy, 1 << hx
    pad = np.full((-(-h // bh) * bh, -(-w // bw) * bw, 2), np.nan)
    pad[:h, :w] = e[..., 1:]
    c = np.nanmean(pad.reshape(pad.shape[0] // bh, bh, pad.shape[1] // bw, bw, 2), axis=(1, 3))

    def code(x):
        return np.clip(np.round(x), 0, top).astype(np.int64)

    return [code(e[..., 0] * ys + y0), code(c[..., 0] * cs + c0), code(c[..., 1] * cs + c0)]


__all__ = ["FORMATS", "MATRICES", "exact", "planes", "ycbcr_to_linear", "ycbcr_to_linear_reference",
           "linear_to_ycbcr", "linear_to_ycbcr_reference", "RowsToYCbCr", "ycbcr_frame", "rgb_to_ycbcr_matrix", "ycbcr_to_rgb_matrix", "code_range"]
