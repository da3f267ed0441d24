"""A Display P3 file written as Radiance HDR: RGBE cannot hold a negative component (its three mantissas are
unsigned bytes beside one shared exponent: Ward, Graphics Gems II, "Real Pixels"), so the colours outside the
sRGB gamut are clipped per channel there as in a PNG, and the command says so once with the count of pixels.

Outside values: the count is colour-science's (P3 codes decoded by its sRGB curve, its P3 -> BT.709 matrix in
float64), with pixels within 2e-3 of the gamut's edge made grey so that float32 rounding cannot move it; the
values read back are OpenCV's Radiance reader's (no lenslab code reads the file).
"""

from __future__ import annotations

import io

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main

colour = pytest.importorskip("colour")
from PIL import Image  # noqa: E402

from lenslab.io.colour.icc_build import profile as build_profile  # noqa: E402
from lenslab.io.colour.icc_chunks import png_with_profile  # noqa: E402

EDGE = 2e-3


def test_a_wide_gamut_file_written_as_radiance_says_what_is_clipped(tmp_path, capsys):
    codes = np.random.default_rng(4).integers(0, 256, (24, 40, 3), dtype=np.uint8)
    linear = colour.RGB_to_RGB(codes / 255, "Display P3", "ITU-R BT.709", None, apply_cctf_decoding=True)
    codes[np.abs(linear.min(axis=-1)) < EDGE] = 128
    linear = colour.RGB_to_RGB(codes / 255, "Display P3", "ITU-R BT.709", None, apply_cctf_decoding=True)
    outside = int((linear.min(axis=-1) < 0).sum())
    assert 0 < outside < codes.shape[0] * codes.shape[1]
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")
    src, out = tmp_path / "p3.png", tmp_path / "out.hdr"
    src.write_bytes(png_with_profile(buf.getvalue(), build_profile("Display P3")))
    assert main(["convert", str(src), "--to", "hdr", "-o", str(out)]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "note:" in line]
    assert notes == [f"lenslab convert: note: {src}: {outside} of {codes.size // 3} pixels hold colours outside "
                     "the sRGB gamut (the file's ICC profile 'Display P3'): clipped per channel"], notes
    back = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    # RGBE keeps 8 bits of mantissa under the exponent of the pixel's largest component: a step of at most
    # 1/128 of that component (Ward), plus float32's rounding
    want = np.maximum(linear, 0)
    assert (np.abs(back - want) <= want.max(axis=-1, keepdims=True) / 128 + 1e-6).all()
    assert (back[linear < 0] == 0).all()  # clipped per channel: exactly 0, as the note says
