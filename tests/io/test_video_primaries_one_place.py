"""Video takes its primaries matrices from the one place stills take theirs (:mod:`lenslab.io.colour.primaries`,
colour-science's ``matrix_RGB_to_RGB``): decoding and encoding PQ and HLG frames, the tables' NumPy paths and
the compiled Y'CbCr passes, both ways (the way back is colour-science's matrix, not an inverse computed by
lenslab). Expected values: colour-science's ``RGB_to_RGB``, ``matrix_RGB_to_RGB``, its transfer functions
and its Y'CbCr matrices (``matrix_YCbCr`` of ``WEIGHTS_YCBCR``)."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

from lenslab.io.colour import primaries
from lenslab.io.video import VideoInfo
from lenslab.io.video import colour as vcolour
from lenslab.io.video import ycbcr

SPACES = colour.RGB_COLOURSPACES
NAMES = {9: "ITU-R BT.2020", 12: "P3-D65"}
REF_WHITE = 203.0  # 1.0 = 203 cd/m2 (ITU-R BT.2408)


def _info(primaries_code, transfer=16, matrix=9):
    return VideoInfo(8, 8, Fraction(24), 1, "hevc", "yuv420p10le", primaries=primaries_code, transfer=transfer,
                     matrix=matrix)


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty cache directory and no matrix kept in memory, and the matrices asked of ``matrix_between``."""
    asked = []
    real = primaries.matrix_between
    monkeypatch.setenv("LENSLAB_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(primaries, "matrix_between", lambda s, t=primaries.REC709: asked.append((s, t)) or real(s, t))
    primaries.h273_matrix.cache_clear()
    yield asked
    primaries.h273_matrix.cache_clear()


@pytest.mark.parametrize("code", [9, 12])
def test_the_matrices_are_colour_sciences_both_ways(fresh, code):
    to709 = colour.matrix_RGB_to_RGB(SPACES[NAMES[code]], SPACES["ITU-R BT.709"], None)
    from709 = colour.matrix_RGB_to_RGB(SPACES["ITU-R BT.709"], SPACES[NAMES[code]], None)
    np.testing.assert_array_equal(vcolour.matrix_to_709(code), to709)
    np.testing.assert_array_equal(vcolour.matrix_from_709(code), from709)
    assert fresh == [(NAMES[code], "ITU-R BT.709"), ("ITU-R BT.709", NAMES[code])]
    # kept in the cache directory: the same bits again, without colour-science
    primaries.h273_matrix.cache_clear()
    np.testing.assert_array_equal(primaries.h273_matrix(code, to_709=False), from709)
    assert len(fresh) == 2
    assert vcolour.matrix_to_709(1) is None and vcolour.matrix_from_709(2) is None  # Rec.709 itself: no matrix


@pytest.mark.parametrize("transfer,code", [(16, 9), (16, 12), (18, 9)], ids=["pq-2020", "pq-p3", "hlg-2020"])
def test_decoding_and_encoding_frames_convert_primaries_as_colour_science(fresh, transfer, code):
    info = _info(code, transfer)
    v = np.random.default_rng(9).uniform(0.05, 0.75, (6, 7, 3))
    if transfer == 16:
        display = colour.models.eotf_ST2084(v) / REF_WHITE
    else:
        display = colour.models.eotf_BT2100_HLG(v, L_B=0, L_W=1000) / REF_WHITE
    expected = colour.RGB_to_RGB(display, SPACES[NAMES[code]], SPACES["ITU-R BT.709"],
                                 chromatic_adaptation_transform=None)
    got = vcolour.to_linear(v, info)
    np.testing.assert_allclose(got, expected, rtol=2e-7, atol=1e-9)  # float32 output: half an ulp and the sums
    # encoding: back to the stream's primaries by colour-science's matrix, then its inverse transfer function
    back = colour.RGB_to_RGB(expected, SPACES["ITU-R BT.709"], SPACES[NAMES[code]],
                             chromatic_adaptation_transform=None)
    if transfer == 16:
        want = colour.models.eotf_inverse_ST2084(np.maximum(back, 0) * REF_WHITE)
    else:
        want = colour.models.eotf_inverse_BT2100_HLG(np.maximum(back, 0) * REF_WHITE, L_B=0, L_W=1000)
    np.testing.assert_allclose(vcolour.from_linear(expected, info), want, rtol=0, atol=1e-12)  # float64 all along
    assert {NAMES[code], "ITU-R BT.709"} == {s for pair in fresh for s in pair}


def test_the_compiled_ycbcr_passes_get_colour_sciences_matrices(fresh):
    info = _info(9)
    dec = ycbcr._decode_args(info, "yuv420p10le")
    enc = ycbcr._encode_args(info, "yuv420p10le", False)
    np.testing.assert_array_equal(dec[5], colour.matrix_RGB_to_RGB(SPACES["ITU-R BT.2020"], SPACES["ITU-R BT.709"], None))
    np.testing.assert_array_equal(enc[3], colour.matrix_RGB_to_RGB(SPACES["ITU-R BT.709"], SPACES["ITU-R BT.2020"], None))
    # the Y'CbCr matrices: colour-science's for BT.709 (1), BT.601 (5, 6; and 2, unspecified, as FFmpeg decodes it)
    # and BT.2020 (9), from its weights
    primaries.ycbcr_weights.cache_clear()
    for tag, name in ((1, "ITU-R BT.709"), (2, "ITU-R BT.601"), (5, "ITU-R BT.601"), (6, "ITU-R BT.601"),
                      (9, "ITU-R BT.2020")):
        assert primaries.ycbcr_weights(tag) == tuple(colour.WEIGHTS_YCBCR[name])
        to_rgb = colour.matrix_YCbCr(K=colour.WEIGHTS_YCBCR[name], bits=1, is_legal=False, is_int=False)
        np.testing.assert_allclose(ycbcr.ycbcr_to_rgb_matrix(tag), to_rgb, rtol=0, atol=1e-15)
        np.testing.assert_allclose(ycbcr.rgb_to_ycbcr_matrix(tag), np.linalg.inv(to_rgb), rtol=0, atol=1e-15)
