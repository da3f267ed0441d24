"""H.273's SDR transfers that are one curve read as one curve: ITU-T H.273 (Table 3) gives transfer
characteristics 1 (BT.709), 6 (BT.601), 14 and 15 (BT.2020 at 10 and 12 bits) the same formula, so a PNG's
``cICP`` chunk or a HEIF's ``nclx`` naming 6, 14 or 15 is decoded as one naming 1 is: lenslab's sRGB decoding
(its stand-in for BT.709's curve, :data:`lenslab.io.colour.png_cicp.SRGB_TRANSFERS`), then BT.2020 or P3-D65
primaries converted to Rec.709, never left as code values taken for linear light. A HEIF ``nclx`` whose
transfer is unspecified (2) is read as sRGB, MIAF's default.

Expected values: colour-science in float64, its sRGB EOTF on the file's codes (cv2's for the PNG written here,
pillow-heif's decoding for the HEIC) and its BT.2020 -> BT.709 matrix. Tolerance: only float32 rounding
separates lenslab's result from them (relative 1e-6; a matrix applied in float32 to values up to 1: 3e-7
absolute), far below sRGB's smallest 8-bit step in linear light, 1 / (255 * 12.92) = 3.0e-4, and far below
the 0.28 that separates a code value of 128 taken as light (0.502) from its sRGB decoding (0.216).
"""

from __future__ import annotations

import numpy as np
import pytest

colour = pytest.importorskip("colour")
cv2 = pytest.importorskip("cv2")

import lenslab.io as lio  # noqa: E402
from lenslab.io.colour.png_cicp import with_cicp  # noqa: E402

BT709 = colour.RGB_COLOURSPACES["ITU-R BT.709"]
TO_709 = {1: np.eye(3), 9: colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"], BT709)}


def _codes() -> np.ndarray:
    codes = np.random.default_rng(11).integers(0, 256, (12, 20, 3), dtype=np.uint8)
    codes[0, :3] = [[0, 0, 0], [255, 255, 255], [128, 128, 128]]
    return codes


def _want(codes: np.ndarray, primaries: int) -> np.ndarray:
    return colour.models.eotf_sRGB(codes.astype(np.float64) / 255.0) @ TO_709[primaries].T


@pytest.mark.parametrize("primaries", [1, 9], ids=["bt709", "bt2020"])
@pytest.mark.parametrize("transfer", [6, 14, 15])
def test_a_png_cicp_of_the_bt709_family_is_decoded_as_bt709(tmp_path, transfer, primaries):
    codes = _codes()
    ok, buf = cv2.imencode(".png", codes[..., ::-1])
    path = tmp_path / f"t{transfer}.png"
    path.write_bytes(with_cicp(buf.tobytes(), (primaries, transfer, 0, 1)))
    img, meta = lio.read(path)
    np.testing.assert_allclose(img, _want(codes, primaries), rtol=1e-6, atol=3e-7)
    assert meta["display_encoded"] is True and "not decoded" not in meta["attributes"].get("note", "")
    assert (meta.get("wide_gamut") == "cICP primaries BT.2020") is (primaries == 9)


@pytest.mark.parametrize("primaries", [1, 9], ids=["bt709", "bt2020"])
@pytest.mark.parametrize("transfer", [6, 14, 15])
def test_a_heif_nclx_of_the_bt709_family_is_decoded_as_bt709(tmp_path, transfer, primaries):
    pillow_heif = pytest.importorskip("pillow_heif")
    codes = _codes()
    heif = pillow_heif.from_bytes("RGB", (codes.shape[1], codes.shape[0]), codes.tobytes())
    heif.info["nclx_profile"] = {"color_primaries": primaries, "transfer_characteristics": transfer,
                                 "matrix_coefficients": 9 if primaries == 9 else 6, "full_range_flag": 1}
    path = tmp_path / f"t{transfer}.heic"
    heif.save(str(path), quality=-1, chroma=444)
    got = np.asarray(pillow_heif.open_heif(str(path), convert_hdr_to_8bit=False, hdr_to_16bit=False))
    img, meta = lio.read(path)
    np.testing.assert_allclose(img, _want(got, primaries), rtol=1e-6, atol=3e-7)
    assert f"transfer {transfer}" in meta["attributes"]["nclx"] and meta["display_encoded"] is True
    assert "not decoded" not in meta["attributes"].get("note", "")
    assert (meta.get("wide_gamut") == "nclx primaries BT.2020") is (primaries == 9)


@pytest.mark.parametrize("primaries", [2, 9], ids=["unspecified", "bt2020"])
def test_a_heif_nclx_with_an_unspecified_transfer_reads_as_srgb(tmp_path, primaries):
    """An ``nclx`` whose transfer is unspecified (2) says nothing of the curve: a HEIF is then sRGB (MIAF's default
    for a file without colour information, and lenslab's rule for an RGB video stream without a transfer tag),
    not code values taken for linear light."""
    pillow_heif = pytest.importorskip("pillow_heif")
    codes = _codes()
    heif = pillow_heif.from_bytes("RGB", (codes.shape[1], codes.shape[0]), codes.tobytes())
    heif.info["nclx_profile"] = {"color_primaries": primaries, "transfer_characteristics": 2,
                                 "matrix_coefficients": 6, "full_range_flag": 1}
    path = tmp_path / "unspecified.heic"
    heif.save(str(path), quality=-1, chroma=444)
    got = np.asarray(pillow_heif.open_heif(str(path), convert_hdr_to_8bit=False, hdr_to_16bit=False))
    img, meta = lio.read(path)
    np.testing.assert_allclose(img, _want(got, 1 if primaries == 2 else primaries), rtol=1e-6, atol=3e-7)
    assert "transfer 2" in meta["attributes"]["nclx"] and "sRGB" in meta["attributes"]["nclx"]
    assert meta["display_encoded"] is True and "not decoded" not in meta["attributes"].get("note", "")
