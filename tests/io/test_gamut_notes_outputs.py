"""The note on a wide-gamut file's colours outside the sRGB gamut counts the pixels of what was written: a warp's
note counts the warped image's pixels and names it (not the input's, which may have four times as many).

Outside values: which pixels lie outside the sRGB gamut is colour-science's answer in float64 (its sRGB decoding
and its matrix from Display P3 to BT.709), on codes whose pixels near the gamut's edge were made grey
(``tests/io/test_wide_gamut_notes.py``, whose helpers write the files: Pillow's PNG, lenslab's Display P3
profile). The pixel totals are counted here from the sizes written.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

pytest.importorskip("colour")
from tests.io.test_wide_gamut_notes import _codes, _linear_709, _notes, _write  # noqa: E402

NOTE = "hold colours outside the sRGB gamut"


def _outside(codes: np.ndarray, name: str = "display-p3") -> int:
    """colour-science's count: pixels with a negative component in linear BT.709."""
    return int((_linear_709(codes, name).min(axis=-1) < 0).sum())


def test_a_warp_counts_the_pixels_of_the_warped_image_and_names_it(tmp_path, capsys):
    """A 112 x 80 Display P3 panorama of 2 x 2 blocks of one colour, warped to a 56 x 40 panorama with the
    nearest filter: each output pixel's centre falls in the middle of one block (x_in = 2 x_out + 0.5), so the
    output holds each block's colour once, and colour-science's count on the 56 x 40 codes is the output's."""
    codes = _codes("display-p3")  # 40 x 56
    blocks = np.kron(codes, np.ones((2, 2, 1), np.uint8))
    src, out = tmp_path / "p3.png", tmp_path / "srgb.png"
    _write(src, blocks, "display-p3")
    outside = _outside(codes)
    assert 0 < outside < codes.shape[0] * codes.shape[1]
    assert main(["warp", str(src), "--from", "equirect", "--to", "equirect", "--size", "56x40", "--filter",
                 "nearest", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    want = (f"lenslab warp: note: {src}: {outside} of {56 * 40} pixels of the warped image {out} {NOTE} (the file's "
            f"ICC profile 'Display P3'): clipped per channel")
    assert _notes(err) == [want], err
    assert f"of {112 * 80} pixels" not in err  # the input's pixels

