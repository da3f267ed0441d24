"""The compiled Y'CbCr passes (lenslab.io.video.ycbcr) against colour-science's Y'CbCr functions (the BT.709, BT.601
and BT.2020 matrices with H.273's limited and full ranges) and its transfer functions, in float64; and against their
NumPy references. Frames are odd-sized so that the last chroma block of 4:2:0 / 4:2:2 is a partial one."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.io.video import VideoInfo  # noqa: E402
from lenslab.io.video.ycbcr import (FORMATS, linear_to_ycbcr, linear_to_ycbcr_reference, planes,  # noqa: E402
                                    ycbcr_to_linear, ycbcr_to_linear_reference)

H, W = 21, 37
K = {1: colour.WEIGHTS_YCBCR["ITU-R BT.709"], 5: colour.WEIGHTS_YCBCR["ITU-R BT.601"],
     9: colour.WEIGHTS_YCBCR["ITU-R BT.2020"]}
# (pixel format, primaries, transfer, matrix, range): H.264's 8-bit 4:2:0, 10-bit 4:2:2, full-range BT.601 4:4:4,
# BT.2020 PQ 10-bit 4:2:0 and full-range 12-bit 4:4:4
CASES = [("yuv420p", 1, 1, 1, 1), ("yuv422p10le", 1, 1, 1, 1), ("yuv444p", 1, 1, 5, 2), ("yuv420p10le", 9, 16, 9, 1),
         ("yuv444p12le", 9, 16, 9, 2)]
M2020 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"], colour.RGB_COLOURSPACES["ITU-R BT.709"])


def _info(case):
    fmt, prim, trc, mat, rng = case
    return VideoInfo(W, H, Fraction(25), 1, "h264", fmt, prim, trc, mat, rng)


def _eotf(v, trc):
    """Code values -> linear Rec.709 by colour-science (float64): BT.1886, or PQ with 1.0 = 203 cd/m2 and BT.2020."""
    if trc == 16:
        return (colour.models.eotf_ST2084(v) / 203.0) @ M2020.T
    return colour.models.eotf_BT1886(v, L_B=0, L_W=1)


def _frame(case, seed):
    """A frame of random codes over the whole code range (out-of-gamut colours included)."""
    fmt = case[0]
    bits = FORMATS[fmt][0]
    frame = av.VideoFrame(W, H, fmt)
    rs = np.random.default_rng(seed)
    for p in planes(frame):
        p[:] = rs.integers(0, 1 << bits, p.shape)
    return frame


def _upsampled(frame):
    """The planes as H x W x 3 codes, each chroma sample repeated over its block (swscale's default upsampling)."""
    _, hx, vy = FORMATS[frame.format.name]
    y, u, v = planes(frame)
    up = [np.repeat(np.repeat(c, 1 << vy, 0), 1 << hx, 1)[:H, :W] for c in (u, v)]
    return np.stack([y[:H, :W], *up], -1).astype(np.float64)


def _curve(v, trc):
    """The transfer function alone (float64, per value), in lenslab's units."""
    return colour.models.eotf_ST2084(v) / 203.0 if trc == 16 else colour.models.eotf_BT1886(v, L_B=0, L_W=1)


def _interpolation_error(trc):
    """The largest error of interpolating the transfer function linearly between 16-bit codes (the table's): its
    deviation from the chord at each interval's midpoint, from colour-science in float64."""
    x = np.arange(65536) / 65535.0
    f = _curve(x, trc)
    return float(np.abs(_curve((x[:-1] + x[1:]) / 2, trc) - (f[:-1] + f[1:]) / 2).max())


def _decode_bound(rgb, trc):
    """What the compiled decoding may differ by from the exact value, per value, derived from its arithmetic:
    R'G'B' in float32 from codes and the matrix (a few roundings of values below 2: 8 x 2^-24) moved along the
    curve's slope; the table's interpolation; its float32 entries and the lerp's two roundings (3 x 2^-24 of the
    value); through BT.2020 -> Rec.709 in float32 (the matrix's absolute values, and 3 x 2^-24 more)."""
    e = np.clip(rgb, 0.0, 1.0)
    h = 1.0 / 65535.0
    slope = np.abs(_curve(np.minimum(e + h, 1.0), trc) - _curve(np.maximum(e - h, 0.0), trc)) / (2 * h)
    f = _curve(e, trc)
    per = _interpolation_error(trc) + slope * 8 * 2.0**-24 + 3 * 2.0**-24 * np.abs(f)
    if trc == 16:
        return per @ np.abs(M2020).T + 3 * 2.0**-24 * (np.abs(f) @ np.abs(M2020).T)
    return per


@pytest.mark.parametrize("case", CASES, ids=[c[0] + f"-m{c[3]}-r{c[4]}" for c in CASES])
def test_decoding_is_colour_sciences_ycbcr_and_eotf(case):
    fmt, _, trc, mat, rng = case
    frame = _frame(case, 1)
    bits = FORMATS[fmt][0]
    rgb = colour.YCbCr_to_RGB(_upsampled(frame), K=K[mat], in_bits=bits, in_legal=rng == 1, in_int=True)
    want = _eotf(np.clip(rgb, 0.0, 1.0), trc)
    got = ycbcr_to_linear(frame, _info(case))
    assert (np.abs(got - want) <= _decode_bound(rgb, trc)).all()
    # the NumPy reference: the same float32 operations, which the compiler may fuse (one rounding fewer each)
    ref = ycbcr_to_linear_reference(*planes(frame), _info(case), fmt, (H, W))
    assert (np.abs(got - ref) <= 2 * _decode_bound(rgb, trc)).all()


@pytest.mark.parametrize("case", CASES, ids=[c[0] + f"-m{c[3]}-r{c[4]}" for c in CASES])
def test_encoding_is_colour_sciences_inverse_eotf_and_ycbcr(case):
    fmt, _, trc, mat, rng = case
    bits, hx, vy = FORMATS[fmt]
    rs = np.random.default_rng(2)
    lin = rs.uniform(-0.1, 1.3, (H, W, 3)) ** 3  # dark values dense, some above white and below black
    lin.reshape(-1, 3)[:4] = [[np.nan, 0, 1], [np.inf, -np.inf, 0], [1, 1, 1], [0, 0, 0]]
    lin[3:9, 2:30] = 0.0  # black runs, as outside a lens's view: whole groups of eight pixels and parts of them
    lin[9, 5:21] = -0.0
    lin = lin.astype(np.float32)
    info = _info(case)
    got = [p[:-(-H // (1 << (vy if k else 0))), :-(-W // (1 << (hx if k else 0)))].astype(np.int64)
           for k, p in enumerate(planes(linear_to_ycbcr(lin, info, fmt)))]
    # outside values: colour-science's inverse EOTF and Y'CbCr encoding (H.273's ranges) in float64, codes unrounded
    v = np.nan_to_num(lin.astype(np.float64), nan=0.0, posinf=1e4, neginf=0.0)
    if trc == 16:
        e = colour.models.eotf_inverse_ST2084(np.maximum(v @ np.linalg.inv(M2020).T, 0) * 203.0)
    else:
        e = colour.models.eotf_inverse_BT1886(np.clip(v, 0, 1), L_B=0, L_W=1)
    ycc = colour.RGB_to_YCbCr(np.clip(e, 0, 1), K=K[mat], out_bits=bits, out_legal=rng == 1, out_int=False)
    ycc = ycc * ((1 << bits) - 1)  # colour-science's float output is in [0, 1]: back to code units
    if rng == 2:
        ycc[..., 1:] += 1 << (bits - 1)  # full range: its float chroma is E'c in [-0.5, 0.5]; H.273 adds 2^(n-1)
    bh, bw = 1 << vy, 1 << hx
    pad = np.full((-(-H // bh) * bh, -(-W // bw) * bw, 3), np.nan)
    pad[:H, :W] = ycc
    chroma = np.nanmean(pad.reshape(pad.shape[0] // bh, bh, pad.shape[1] // bw, bw, 3), axis=(1, 3))
    for g, w in zip(got, [ycc[..., 0], chroma[..., 1], chroma[..., 2]]):
        # the inverse curve's table is within 0.07 of a 16-bit code of colour-science's (test_video_colour), i.e.
        # 0.07 / 65535 of the range, at most 1.9 times that through the matrix: a rounding can flip only where the
        # exact code lies within 0.001 of a half
        near_half = np.abs(w - np.floor(w) - 0.5) < 0.001
        assert (g == np.round(w)).all() or ((np.abs(g - np.round(w)) <= 1) & ((g == np.round(w)) | near_half)).all()
    ref = linear_to_ycbcr_reference(lin, info, fmt)
    for g, r in zip(got, ref):
        assert (np.abs(g - r) <= 1).all()


def test_white_and_black_are_the_standards_codes():
    """BT.709 limited range: linear 1.0 is Y' = 940 (10 bits) / 235 (8 bits) with Cb = Cr = 512 / 128, and back
    exactly (swscale gives 943 and 65283/65535 for these)."""
    for fmt, white, grey in (("yuv420p10le", 940, 512), ("yuv420p", 235, 128)):
        info = _info((fmt, 1, 1, 1, 1))
        lin = np.zeros((H, W, 3), np.float32)
        lin[:, W // 2:] = 1.0
        f = linear_to_ycbcr(lin, info, fmt)
        y, u, v = planes(f)
        assert (y[:H, W // 2 + 1:W] == white).all() and (y[:H, :W // 2] == 64 * white // 940).all()
        assert (u[:-(-H // 2), :-(-W // 2)] == grey).all() and (v[:-(-H // 2), :-(-W // 2)] == grey).all()
        np.testing.assert_array_equal(ycbcr_to_linear(f, info)[:, W // 2 + 1:], 1.0)


def test_a_window_is_the_whole_frames_pixels_and_the_rest_is_untouched():
    case = CASES[1]
    frame = _frame(case, 3)
    whole = ycbcr_to_linear(frame, _info(case))
    out = np.full((H, W, 3), -7.0, np.float32)
    ycbcr_to_linear(frame, _info(case), (3, 17, 5, 30), out)
    np.testing.assert_array_equal(out[3:17, 5:30], whole[3:17, 5:30])
    out[3:17, 5:30] = -7.0
    assert (out == -7.0).all()
