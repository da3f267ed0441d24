"""``convert`` keeps the precision of an input of more than 8 bits, as it keeps a 16-bit PNG's: a 10- or 12-bit
HEIC converted to PNG is written with 16-bit samples, so its 1024 or 4096 levels stay distinct instead of being
merged four or sixteen to an 8-bit code; ``--bits 8`` still asks for 8.

Expected values: the HEIC's codes as pillow-heif decodes them at the file's depth, ``c``, and H.273's value of
each, ``c / (2^n - 1)``, which a 16-bit PNG holds as ``c / (2^n - 1) * 65535`` (float64 here). Tolerance: one
16-bit code, the rounding of the sRGB round trip through float32 linear light (a 16-bit step is 1.5e-5; float32
keeps 2^-24 of each value); the 10- and 12-bit steps, 64 and 16 codes, are far larger.
"""

from __future__ import annotations

import numpy as np
import pytest

pillow_heif = pytest.importorskip("pillow_heif")
cv2 = pytest.importorskip("cv2")

from lenslab.cli.main import main  # noqa: E402


def _ramp_heic(path, bits: int):
    """A lossless HEIC of every ``bits``-bit code along a ramp (pillow-heif takes 16-bit samples and keeps their
    top ``bits`` bits)."""
    top = (1 << bits) - 1
    codes = np.broadcast_to(np.linspace(0, top, 256).round().astype(np.uint16)[None, :, None], (8, 256, 3))
    before = pillow_heif.options.SAVE_HDR_TO_12_BIT
    pillow_heif.options.SAVE_HDR_TO_12_BIT = bits == 12
    try:
        shifted = np.ascontiguousarray(codes << (16 - bits))
        pillow_heif.from_bytes("RGB;16", (256, 8), shifted.tobytes()).save(str(path), quality=-1, chroma=444)
    finally:
        pillow_heif.options.SAVE_HDR_TO_12_BIT = before
    heif = pillow_heif.open_heif(str(path), convert_hdr_to_8bit=False, hdr_to_16bit=False)
    assert int(heif.info["bit_depth"]) == bits
    return np.asarray(heif).astype(np.float64)


@pytest.mark.parametrize("bits", [10, 12])
def test_a_10_or_12_bit_heic_converts_to_a_16_bit_png(tmp_path, bits):
    codes = _ramp_heic(tmp_path / "photo.heic", bits)
    assert main(["convert", str(tmp_path / "photo.heic"), "-o", str(tmp_path / "photo.png"), "-q"]) == 0
    out = cv2.imread(str(tmp_path / "photo.png"), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert out.dtype == np.uint16
    want = codes / ((1 << bits) - 1) * 65535
    assert np.abs(out - want).max() <= 1
    assert len(np.unique(out[0, :, 1])) == len(np.unique(codes[0, :, 1]))  # every level kept apart


def test_bits_8_still_asks_for_8(tmp_path):
    _ramp_heic(tmp_path / "photo.heic", 10)
    assert main(["convert", str(tmp_path / "photo.heic"), "-o", str(tmp_path / "photo.png"), "--bits", "8",
                 "-q"]) == 0
    assert cv2.imread(str(tmp_path / "photo.png"), cv2.IMREAD_UNCHANGED).dtype == np.uint8
