"""Video colour: the transfer functions of video streams (colour-science's), their tables, and the compiled
passes that apply them to whole frames.

- :func:`to_linear` / :func:`from_linear`: code values <-> linear Rec.709, float64, value by value: the
  references.
- :func:`codes16_to_linear` (NumPy) and :func:`codes16_to_linear_compiled` (one pass without the GIL,
  ``src/native/video.cpp``): 16-bit codes -> linear light by the table of :func:`to_linear` at every code, so
  the values are the same bits (BT.2020's matrix aside: float64 sums in another order, one float32 rounding).
- :func:`linear_to_codes16`: linear light -> 16-bit codes in one compiled pass, NaN and infinities made finite
  as :func:`from_linear` does, Rec.709 -> BT.2020 where the stream is wide, the inverse transfer function as a
  table over float32 bit patterns (``KNOT_SHIFT``: 1024 knots a binade from 2^-60 to 2^7) interpolated linearly
  within each knot interval. Against colour-science the codes agree within one 16-bit step
  (``tests/io/test_video_colour.py``). HLG, whose EOTF mixes the channels, stays in NumPy both ways.

These passes serve the frames that go through swscale's matrix and range (HLG, RGB-coded streams, other pixel
formats); planar Y'CbCr frames go to and from linear light in one pass each way (:mod:`lenslab.io.video.ycbcr`). The tables are built with
colour-science the first time a curve is met and kept in lenslab's cache directory (:func:`cached`), so a run
does not wait for colour-science's import (1.2 to 2.4 s here).
"""

from __future__ import annotations

import os
from functools import lru_cache

import numpy as np

from lenslab.io.colour.primaries import H273_PRIMARIES, h273_matrix

#: HDR reference white (ITU-R BT.2408): the luminance lenslab's 1.0 stands for in PQ and HLG video
REFERENCE_WHITE = 203.0
BT2020 = 9  # AVCOL_PRI_BT2020
KNOT_SHIFT = 13  # 2^(23 - 13) = 1024 knots per binade of float32
LOW, HIGH = -60, 7  # the table spans [2^LOW, 2^HIGH]; below: the code of 0; above: the code of 2^HIGH


#: OpenColorIO display (as the built-in configs name them, lower case, up to " - display") -> the
#: (primaries, transfer, matrix) tags its code values carry in a video stream
DISPLAY_TAGS = {"rec.2100-pq": (9, 16, 9), "rec.2100-hlg": (9, 18, 9), "st2084-p3-d65": (12, 16, 9),
                "srgb": (1, 13, 1), "rec.1886 rec.709": (1, 1, 1), "gamma 2.2 rec.709": (1, 4, 1),
                "display p3": (12, 13, 1)}


def display_tags(display: str) -> tuple[int, int, int]:
    """Video tags for the code values of an OpenColorIO display; FormatError for displays without them."""
    from lenslab.errors import FormatError

    key = display.lower().split(" - display")[0]
    if key not in DISPLAY_TAGS:
        raise FormatError(f"{display}: no video colour tags are known for this display; use one of "
                          f"{', '.join(DISPLAY_TAGS)}")
    return DISPLAY_TAGS[key]


def threads() -> int:
    """Threads the colour passes use: the CPUs this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def _native():
    try:
        from lenslab import cxx_kernels
    except ImportError as exc:  # a source tree used without installing it
        from lenslab.errors import FormatError

        raise FormatError("lenslab's compiled kernels are not built: install lenslab with `pip install -e .` "
                          f"(needs a C++17 compiler and CMake) ({exc})") from None
    return cxx_kernels


def linear_from_codes(codes: np.ndarray, table: np.ndarray, matrix: np.ndarray | None = None,
                      window: tuple[int, int, int, int] | None = None, out: np.ndarray | None = None,
                      origin: tuple[int, int] = (0, 0)) -> np.ndarray:
    """16-bit codes (uint16 H x W x 3) -> ``table[codes]`` as float32 (``table``: 65536 float32), or with
    ``matrix`` (3 x 3) ``table[codes] @ matrix.T`` (``table``: 65536 float64, the sums in float64).

    ``window`` ``(row0, row1, col0, col1)``: only those pixels are converted (those a warp reads), the others
    are 0, and their memory is never touched. ``out``: a float32 frame to write into (reused from frame to
    frame: outside the window it keeps what it held). ``origin``: the frame row and column of ``codes[0, 0]``
    when ``codes`` is a crop of the frame ``out`` around the window."""
    codes = np.ascontiguousarray(codes, dtype=np.uint16)
    if out is None:
        out = np.empty(codes.shape, np.float32) if window is None else np.zeros(codes.shape, np.float32)
    h, w = out.shape[:2]
    r0, r1, c0, c1 = window or (0, h, 0, w)
    e32, e64 = np.empty(0, np.float32), np.empty(0, np.float64)
    if matrix is None:
        t32, t64, m = np.ascontiguousarray(table, np.float32), e64, e64
    else:
        t32, t64, m = e32, np.ascontiguousarray(table, np.float64), np.ascontiguousarray(matrix, np.float64)
    _native().linear_from_codes(codes, t32, t64, m, out, r0, r1, c0, c1, origin[0], origin[1], threads())
    return out


def knots() -> np.ndarray:
    """The float32 values of an inverse table's knots, ``2^LOW`` to ``2^HIGH``, ``2^(23 - KNOT_SHIFT)`` a binade."""
    lo = np.array(2.0**LOW, np.float32).view(np.uint32)
    hi = np.array(2.0**HIGH, np.float32).view(np.uint32)
    return np.arange(int(lo), int(hi) + 1, 1 << KNOT_SHIFT, dtype=np.uint32).view(np.float32)


def codes_from_linear(image: np.ndarray, table: np.ndarray | None, zero: float,
                      matrix: np.ndarray | None = None) -> np.ndarray:
    """float32 H x W x 3 -> 16-bit codes (uint16): NaN -> 0, +-inf -> 1e4 / 0, ``matrix`` (3 x 3) applied
    when given, then the curve ``table`` at :func:`knots` (``zero`` below the first), interpolated linearly,
    or with no table a clamp to [0, 1]; times 65535, rounded half to even."""
    image = np.ascontiguousarray(image[..., :3], dtype=np.float32)
    out = np.empty(image.shape, np.uint16)
    b0 = int(np.array(2.0**LOW, np.float32).view(np.uint32))
    _native().codes_from_linear(image, np.empty(0, np.float64) if matrix is None else np.ascontiguousarray(matrix),
                                np.empty(0, np.float32) if table is None else np.ascontiguousarray(table, np.float32),
                                b0, KNOT_SHIFT, float(zero), out, threads())
    return out


CACHE_VERSION = 2


def cached(name: str, length: int, dtype, build) -> np.ndarray:
    """The video table ``name``, built with colour-science the first time and kept in lenslab's cache
    directory (:func:`lenslab.srgb.cache_dir`): importing colour-science costs a second or more, which a short
    clip would wait for on every run."""
    from lenslab.srgb import cached_table

    return cached_table(name, length, dtype, build, prefix=f"video-v{CACHE_VERSION}")


#: H.273 colour primaries converted to and from Rec.709 (:data:`lenslab.io.colour.primaries.H273_PRIMARIES`)
WIDE_PRIMARIES = H273_PRIMARIES


def matrix_to_709(primaries: int) -> np.ndarray | None:
    """Linear RGB in the H.273 ``primaries`` -> linear Rec.709 (float64 3 x 3), or None for Rec.709 itself and
    primaries read as Rec.709: :func:`lenslab.io.colour.primaries.h273_matrix`."""
    return h273_matrix(primaries)


def matrix_from_709(primaries: int) -> np.ndarray | None:
    """Linear Rec.709 -> linear RGB in the H.273 ``primaries`` (float64 3 x 3), or None: colour-science's matrix
    (:func:`lenslab.io.colour.primaries.h273_matrix`), the way back of :func:`matrix_to_709`."""
    return h273_matrix(primaries, to_709=False)


def gamut_name(primaries: int) -> str | None:
    """What :data:`lenslab.io.colour.gamut.WIDE_GAMUT` says for frames converted from these H.273 primaries
    (``colour primaries P3-D65``), or None for frames on Rec.709's: the codes are integers, so every negative
    component of a converted frame is a colour outside the sRGB gamut."""
    return f"colour primaries {WIDE_PRIMARIES[int(primaries)]}" if is_wide(primaries) else None


def is_wide(primaries: int) -> bool:
    """Whether frames of these H.273 primaries are converted to Rec.709 (:data:`WIDE_PRIMARIES`)."""
    return int(primaries) in WIDE_PRIMARIES


def to_linear(codes: np.ndarray, info) -> np.ndarray:
    """Code values in [0, 1] (H x W x 3) -> linear Rec.709 float32, by the stream's transfer and primaries."""
    lin = _eotf(codes.astype(np.float64), info.curve)
    if is_wide(info.primaries):
        from lenslab.io.colour.primaries import to_rec709

        to_rec709(lin, matrix_to_709(info.primaries))
    return lin.astype(np.float32)


def _eotf(v: np.ndarray, curve: str) -> np.ndarray:
    """Code values (float64, ..., 3) -> display light (float64) by the stream's transfer function."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    if curve == "pq":
        lin = colour.models.eotf_ST2084(v) / REFERENCE_WHITE
    elif curve == "hlg":
        lin = colour.models.eotf_BT2100_HLG(v, L_B=0, L_W=1000) / REFERENCE_WHITE
    elif curve == "srgb":
        lin = colour.cctf_decoding(v, "sRGB")
    else:
        lin = colour.models.eotf_BT1886(v, L_B=0, L_W=1)
    return lin


def from_linear(image: np.ndarray, info) -> np.ndarray:
    """Linear Rec.709 (H x W x 3) -> code values in [0, 1], the inverse of :func:`to_linear`."""
    lin = np.nan_to_num(np.asarray(image, np.float64), nan=0.0, posinf=1e4, neginf=0.0)
    if is_wide(info.primaries):
        lin = lin @ matrix_from_709(info.primaries).T
    return _eotf_inverse(lin, info.curve)


def _eotf_inverse(lin: np.ndarray, curve: str, bounded: bool = True) -> np.ndarray:
    """Finite linear light (float64, ..., 3, in the stream's primaries) -> code values in [0, 1] (``bounded``
    False: the curve continued past its ends, for a table whose interpolation must not straddle a clamp)."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    lin = np.maximum(lin, 0.0)
    top = 1.0 if bounded else np.inf
    if curve == "pq":
        v = colour.models.eotf_inverse_ST2084(lin * REFERENCE_WHITE)
    elif curve == "hlg":
        v = colour.models.eotf_inverse_BT2100_HLG(lin * REFERENCE_WHITE, L_B=0, L_W=1000)
    elif curve == "srgb":
        v = colour.cctf_encoding(np.minimum(lin, top), "sRGB")
    else:
        v = colour.models.eotf_inverse_BT1886(np.minimum(lin, top), L_B=0, L_W=1)
    return np.clip(v, 0.0, top)


@lru_cache(maxsize=8)
def encode_table(curve: str) -> tuple[np.ndarray, float]:
    """(:func:`_eotf_inverse` at the knots of :mod:`lenslab.io.video.colour`, float32; the code of 0), cached."""
    x = knots()
    t = cached(f"inverse-{curve}-{LOW}-{HIGH}-{KNOT_SHIFT}", len(x) + 1, np.float32,
               lambda: _eotf_inverse(np.concatenate([[0.0], x.astype(np.float64)]), curve, bounded=False))
    return t[1:], float(t[0])


def linear_to_codes16(image: np.ndarray, info, encoded: bool = False) -> np.ndarray:
    """Linear Rec.709 (float32 H x W x 3; ``encoded``: code values in [0, 1]) -> 16-bit codes (uint16), in
    one compiled pass: ``round(from_linear(image) * 65535)`` with the inverse curve tabulated (HLG, whose
    inverse mixes the channels, in NumPy)."""
    if encoded:
        return codes_from_linear(image, None, 0.0, None)
    if info.curve == "hlg":
        return np.round(from_linear(image[..., :3], info) * 65535.0).astype(np.uint16)
    wide = matrix_from_709(info.primaries) if is_wide(info.primaries) else None
    return codes_from_linear(image, *encode_table(info.curve), wide)


@lru_cache(maxsize=8)
def decode_table(curve: str, wide: bool) -> np.ndarray:
    """:func:`to_linear` of every 16-bit code value (65536 x 1 float32, or float64 for BT.2020, whose matrix
    comes after): a decoded frame is then one lookup, the same values as the transfer function's. Built with
    colour-science once and kept in lenslab's cache directory (:func:`lenslab.io.video.colour.cached`)."""
    dtype = np.float64 if wide else np.float32
    return cached(f"decode-{curve}-{np.dtype(dtype).name}", 65536, dtype,
                  lambda: _eotf(np.arange(65536, dtype=np.float64) / 65535.0, curve))


def codes16_to_linear(codes: np.ndarray, info) -> np.ndarray:
    """16-bit code values (uint16 H x W x 3) -> linear Rec.709 float32: :func:`to_linear` by table lookup.

    HLG's EOTF scales each pixel by a power of its luminance (the OOTF), so it mixes the channels and
    is computed pixel by pixel; the other curves act on each value alone."""
    if info.curve == "hlg":
        return to_linear(codes.astype(np.float64) / 65535.0, info)
    wide = is_wide(info.primaries)
    lin = decode_table(info.curve, wide)[codes]
    if wide:
        return (lin @ matrix_to_709(info.primaries).T).astype(np.float32)
    return lin


def codes16_to_linear_compiled(codes: np.ndarray, info, window: tuple[int, int, int, int] | None = None,
                               out: np.ndarray | None = None, origin: tuple[int, int] = (0, 0)) -> np.ndarray:
    """:func:`codes16_to_linear` (its NumPy reference) in one compiled pass, HLG aside (whose codes must be the
    whole frame); ``window``, ``out`` and ``origin``: see :func:`linear_from_codes`."""
    if info.curve == "hlg":
        return codes16_to_linear(codes, info)
    wide = is_wide(info.primaries)
    return linear_from_codes(codes, decode_table(info.curve, wide), matrix_to_709(info.primaries) if wide else None,
                             window, out, origin)


__all__ = ["to_linear", "from_linear", "codes16_to_linear", "codes16_to_linear_compiled", "linear_to_codes16",
           "linear_from_codes", "codes_from_linear", "matrix_to_709", "matrix_from_709", "is_wide", "gamut_name", "cached", "knots", "display_tags", "DISPLAY_TAGS"]
