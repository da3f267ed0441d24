"""HEIC files read as their codes and colour information say, against values from outside lenslab.

Every file is written here by pillow-heif's encoder (libheif, x265). The expected light is pillow-heif's own
decoding of the file (the code values libheif gives, at the file's depth) run through colour-science in
float64: the sRGB curve, ST 2084 (PQ) and BT.2100 HLG (L_W = 1000 cd/m², L_B = 0) over 203 cd/m² (BT.2408's
reference white, lenslab's 1.0 for video), and colour-science's BT.2020 / P3-D65 / Adobe RGB -> BT.709
matrices; for the ICC case littleCMS too (Pillow's ImageCms), as tests/io/test_icc_profiles.py does.

Tolerances: lenslab decodes the same codes as the reference, so only float32 rounding separates them
(relative 2^-24 of each value, 1e-6 asked; a primaries matrix applied in float32 to values up to 1, within
2 ulp of 1, 3e-7 absolute): far below a code step in linear light, the smallest of which is sRGB's first
8-bit step, 1 / (255 * 12.92) = 3.0e-4 (PQ's and HLG's first steps are smaller still, but there the values
are too, and the relative bound holds). An ICC profile's colorants are s15.16 numbers adapted to D50 by the
profile's maker: Ghostscript's a98.icc is 3.2e-5 of linear light from colour-science's Adobe RGB (1998)
(measured), asked within 1e-4, a third of the smallest 8-bit step; littleCMS rounds its output to an
8-bit code: within 1 code.
"""

from __future__ import annotations

import io
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

pillow_heif = pytest.importorskip("pillow_heif")
colour = pytest.importorskip("colour")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402

A98 = Path("/usr/share/color/icc/ghostscript/a98.icc")  # Debian's libgs-common
BT709 = colour.RGB_COLOURSPACES["ITU-R BT.709"]
REFERENCE_WHITE = 203.0  # ITU-R BT.2408


def to_709(name: str) -> np.ndarray:
    return colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES[name], BT709)


def srgb(codes, maxval=255) -> np.ndarray:
    return colour.models.eotf_sRGB(np.asarray(codes, np.float64) / maxval)


def write_heic(path, codes: np.ndarray, bits: int = 8, nclx=None, icc=None, **save) -> Path:
    """``codes`` (H x W x C, uint8, or uint16 spanning 16 bits for 10 and 12-bit files) saved by pillow-heif,
    losslessly coded where x265 allows it (quality -1, 4:4:4)."""
    h, w, c = codes.shape
    mode = {3: "RGB", 4: "RGBA"}[c] + (";16" if codes.dtype == np.uint16 else "")
    heif = pillow_heif.from_bytes(mode, (w, h), np.ascontiguousarray(codes).tobytes())
    if nclx is not None:
        heif.info["nclx_profile"] = dict(zip(("color_primaries", "transfer_characteristics", "matrix_coefficients",
                                              "full_range_flag"), nclx))
    if icc is not None:
        heif.info["icc_profile"] = icc
    before = pillow_heif.options.SAVE_HDR_TO_12_BIT  # (a module option: 16-bit codes go to 10 bits by default)
    pillow_heif.options.SAVE_HDR_TO_12_BIT = bits == 12
    try:
        heif.save(str(path), quality=-1, chroma=444, **save)
    finally:
        pillow_heif.options.SAVE_HDR_TO_12_BIT = before
    return Path(path)


def decoded(path) -> tuple[np.ndarray, int]:
    """pillow-heif's codes of the primary image at the file's own depth, and that depth."""
    heif = pillow_heif.open_heif(str(path), convert_hdr_to_8bit=False, hdr_to_16bit=False)
    return np.asarray(heif).astype(np.int64), int(heif.info["bit_depth"])


def _random(shape, dtype=np.uint8, seed=0):
    top = np.iinfo(dtype).max
    codes = np.random.default_rng(seed).integers(0, top + 1, shape, dtype=dtype)
    codes[0, :3] = [[0] * shape[2], [top] * shape[2], [top // 2] * shape[2]]
    return codes


def test_an_8_bit_srgb_heic_reads_as_colour_science_decodes_its_codes(tmp_path):
    path = write_heic(tmp_path / "srgb.heic", _random((16, 24, 3)))
    codes, bits = decoded(path)
    img, meta = lio.read(path)
    assert bits == 8 and img.dtype == np.float32 and img.shape == (16, 24, 3)
    np.testing.assert_allclose(img, srgb(codes), rtol=1e-6, atol=1e-9)
    assert meta["format"] == "heif" and meta["bit_depth"] == 8 and meta["display_encoded"] is True
    assert meta["channels"] == ["R", "G", "B"] and "transfer 13" in meta["attributes"]["nclx"]
    raw, _ = lio.read(path, raw=True)  # the stored codes over 255
    np.testing.assert_allclose(raw, codes / 255.0, rtol=1e-6)


@pytest.mark.parametrize("bits", [10, 12])
@pytest.mark.parametrize("transfer", [16, 18], ids=["pq", "hlg"])
def test_hdr_heic_decodes_to_linear_light_as_bt2100_says(tmp_path, bits, transfer):
    path = write_heic(tmp_path / "hdr.heic", _random((16, 24, 3), np.uint16, seed=bits), bits, nclx=(9, transfer, 9, 1))
    codes, depth = decoded(path)
    assert depth == bits and codes.max() <= (1 << bits) - 1
    e = codes / float((1 << bits) - 1)  # H.273 full range: E' = D / (2^n - 1)
    if transfer == 16:
        light = colour.models.eotf_ST2084(e)
    else:
        light = colour.models.eotf_BT2100_HLG(e, L_B=0, L_W=1000)
    want = (light / REFERENCE_WHITE) @ to_709("ITU-R BT.2020").T
    img, meta = lio.read(path)
    np.testing.assert_allclose(img, want, rtol=1e-6, atol=1e-9)
    assert meta["bit_depth"] == bits and meta["display_encoded"] is False
    assert f"transfer {transfer}" in meta["attributes"]["nclx"] and "primaries 9" in meta["attributes"]["nclx"]
    assert meta.get("wide_gamut") == "nclx primaries BT.2020"
    if transfer == 16:  # PQ's peak, 10000 cd/m2, wherever the file holds the top code in all three channels
        top = np.all(codes == (1 << bits) - 1, axis=-1)
        assert top.any() and np.allclose(img[top], 10000.0 / REFERENCE_WHITE, rtol=1e-6)


def test_pillow_heifs_16_bit_output_is_the_code_shifted_so_lenslab_reads_the_codes_themselves(tmp_path):
    """Why lenslab asks pillow-heif for codes at their own depth: its 16-bit output of a 10-bit code c is
    c << 6, whose value over 65535 falls short of c / 1023 by up to 0.96 of a 10-bit step (at white)."""
    path = write_heic(tmp_path / "pq.heic", _random((8, 8, 3), np.uint16), 10, nclx=(9, 16, 9, 1))
    codes, _ = decoded(path)
    shifted = np.asarray(pillow_heif.open_heif(str(path), convert_hdr_to_8bit=False)).astype(np.int64)
    assert np.array_equal(shifted, codes << 6)
    assert (1023 / 1023 - (1023 << 6) / 65535) * 1023 > 0.95


def test_alpha_is_coverage_and_the_colour_premultiplied_in_linear_light(tmp_path):
    codes = _random((16, 24, 4), seed=3)
    path = write_heic(tmp_path / "rgba.heic", codes)
    got, _ = decoded(path)
    img, meta = lio.read(path)
    alpha = got[..., 3] / 255.0
    assert meta["channels"] == ["R", "G", "B", "A"]
    np.testing.assert_allclose(img[..., 3], alpha, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(img[..., :3], srgb(got[..., :3]) * alpha[..., None], rtol=1e-6, atol=1e-9)


def test_nclx_display_p3_srgb_codes_are_converted_to_rec709(tmp_path):
    path = write_heic(tmp_path / "p3.heic", _random((16, 24, 3), seed=4), nclx=(12, 13, 6, 1))
    codes, _ = decoded(path)
    img, meta = lio.read(path)
    # the matrix applied in float32 to values up to 1 (coefficients up to 1.23): within 2 ulp of 1, 2.4e-7
    np.testing.assert_allclose(img, srgb(codes) @ to_709("P3-D65").T, rtol=1e-6, atol=3e-7)
    assert "P3-D65" in meta["attributes"]["note"] and meta["wide_gamut"] == "nclx primaries P3-D65"


@pytest.mark.parametrize("bits", [8, 10])
def test_an_embedded_icc_profile_is_applied_as_in_png(tmp_path, bits):
    if not A98.is_file():
        pytest.skip(f"{A98} is absent (Debian's libgs-common, which .ci/run installs)")
    icc = A98.read_bytes()
    dtype = np.uint8 if bits == 8 else np.uint16
    path = write_heic(tmp_path / "a98.heic", _random((16, 24, 3), dtype, seed=5), bits, icc=icc)
    codes, depth = decoded(path)
    img, meta = lio.read(path)
    assert depth == bits and meta["bit_depth"] == bits
    assert "applied" in meta["attributes"]["icc"] and "not applied" not in meta["attributes"]["icc"]
    e = codes / float((1 << bits) - 1)
    want = e ** (563 / 256) @ to_709("Adobe RGB (1998)").T  # the profile's curv: gamma 563/256
    np.testing.assert_allclose(img, want, rtol=0, atol=1e-4)
    if bits != 8:
        return
    from PIL import Image, ImageCms

    t = ImageCms.buildTransform(ImageCms.ImageCmsProfile(io.BytesIO(icc)), ImageCms.createProfile("sRGB"), "RGB",
                                "RGB", ImageCms.Intent.RELATIVE_COLORIMETRIC)
    theirs = np.asarray(ImageCms.applyTransform(Image.fromarray(codes.astype(np.uint8)), t)).astype(np.float64)
    ours = colour.models.eotf_inverse_sRGB(np.clip(img.astype(np.float64), 0, 1)) * 255
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1.0)


def _two_images(path) -> Path:
    big = _random((16, 24, 3), seed=6)
    heif = pillow_heif.from_bytes("RGB", (24, 16), big.tobytes())
    heif.add_frombytes("RGB", (8, 6), np.full((6, 8, 3), 200, np.uint8).tobytes())
    heif.save(str(path), quality=-1, chroma=444, primary_index=1)
    return Path(path)


def test_a_multi_image_file_reads_its_primary_image_and_others_by_index(tmp_path):
    path = _two_images(tmp_path / "two.heic")
    heif = pillow_heif.open_heif(str(path))
    assert len(heif) == 2 and heif.primary_index == 1
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        img, meta = lio.read(path)
    assert img.shape == (6, 8, 3)  # the primary image, not the first
    np.testing.assert_allclose(img, srgb(np.asarray(heif[1]).astype(np.int64)), rtol=1e-6)
    assert "2 top-level images" in meta["attributes"]["images"]
    assert any("two.heic:INDEX" in str(w.message) for w in caught)
    first, meta0 = lio.read(f"{path}:0")
    assert first.shape == (16, 24, 3) and meta0["image_index"] == 0
    np.testing.assert_allclose(first, srgb(np.asarray(heif[0]).astype(np.int64)), rtol=1e-6)
    with pytest.raises(lio.FormatError, match=r"no image '2'.*0: 24 x 16, 1: 8 x 6 \(primary\)"):
        lio.read(f"{path}:2")


def test_info_describes_size_depth_colour_alpha_and_images(tmp_path, capsys):
    codes = _random((16, 24, 4), np.uint16, seed=7)
    path = tmp_path / "hdr.heic"
    heif = pillow_heif.from_bytes("RGBA;16", (24, 16), codes.tobytes())
    heif.info["nclx_profile"] = {"color_primaries": 9, "transfer_characteristics": 18, "matrix_coefficients": 9,
                                 "full_range_flag": 1}
    heif.save(str(path), quality=-1, chroma=444)
    assert main(["info", "--json", str(path)]) == 0
    (d,) = json.loads(capsys.readouterr().out)
    assert (d["format"], d["width"], d["height"], d["bit_depth"]) == ("heif", 24, 16, 10)
    assert d["channels"] == ["R", "G", "B", "A"]
    assert d["attributes"]["nclx"] == "primaries 9, transfer 18 HLG (ARIB STD-B67), matrix 9, full range"
    assert d["attributes"]["images"] == "1 top-level image"
    assert main(["info", str(path)]) == 0
    text = capsys.readouterr().out
    assert "HEIF 24 x 16, 4 channel(s) R,G,B,A, uint 10-bit" in text and "HLG" in text


def test_premultiplied_alpha_in_the_file_becomes_premultiplied_linear_light(tmp_path):
    """A ``prem`` file holds colour codes premultiplied by alpha; lenslab divides them back to straight codes
    (rounded to a code: half a code of straight colour, at most 0.5 / 255 * 2.27 = 4.5e-3 of straight linear
    light where sRGB is steepest, times alpha once premultiplied) before decoding."""
    codes = _random((16, 24, 4), seed=8)
    codes[..., :3] = np.minimum(codes[..., :3], codes[..., 3:])  # colour never above alpha: premultiplied codes
    path = tmp_path / "prem.heic"
    pillow_heif.from_bytes("RGBa", (24, 16), codes.tobytes()).save(str(path), quality=-1, chroma=444)
    heif = pillow_heif.open_heif(str(path))
    assert heif.premultiplied_alpha
    got = np.asarray(heif).astype(np.float64)
    a = got[..., 3:] / 255.0
    straight = np.divide(got[..., :3] / 255.0, a, out=np.zeros_like(got[..., :3]), where=a > 0)
    img, meta = lio.read(path)
    np.testing.assert_allclose(img[..., 3:], a, rtol=1e-6)
    err = np.abs(img[..., :3] - colour.models.eotf_sRGB(np.clip(straight, 0, 1)) * a)
    assert np.all(err <= 4.5e-3 * a + 1e-6), float((err - 4.5e-3 * a).max())
    assert "premultiplied in the file" in meta["attributes"]["alpha"]


def test_grey_10_bit_and_tiled_grid_files_read_at_their_size_and_depth(tmp_path):
    grey = _random((16, 24, 1), np.uint16, seed=9)[..., 0]
    path = tmp_path / "grey.heic"
    pillow_heif.from_bytes("L;16", (24, 16), grey.tobytes()).save(str(path), quality=-1)
    codes, bits = decoded(path)
    img, meta = lio.read(path)
    assert bits == 10 and meta["channels"] == ["Y"] and img.shape == (16, 24, 1)
    np.testing.assert_allclose(img[..., 0], srgb(codes, 1023), rtol=1e-6, atol=1e-9)
    before = pillow_heif.options.GRID_TILE_SIZE
    pillow_heif.options.GRID_TILE_SIZE = 64  # as phones write large photos: a grid of tiles
    try:
        write_heic(tmp_path / "grid.heic", _random((100, 150, 3), seed=10))
    finally:
        pillow_heif.options.GRID_TILE_SIZE = before
    heif = pillow_heif.open_heif(str(tmp_path / "grid.heic"))
    assert heif.info["tiling"]["num_columns"] == 3
    img, _ = lio.read(tmp_path / "grid.heic")
    np.testing.assert_allclose(img, srgb(np.asarray(heif).astype(np.int64)), rtol=1e-6, atol=1e-9)


def test_a_selected_image_is_budgeted_before_it_is_decoded(tmp_path):
    """The budget reads the primary image's size; another image picked by index is held to the same rule: a
    4096 x 4096 black image in a 5 kB file (201 MB of float32) is refused in one line, the small primary read."""
    path = tmp_path / "hidden.heic"
    heif = pillow_heif.from_bytes("RGB", (8, 6), np.zeros((6, 8, 3), np.uint8).tobytes())
    heif.add_frombytes("RGB", (4096, 4096), bytes(4096 * 4096 * 3))
    heif.save(str(path), quality=50, primary_index=0, enc_params={"preset": "ultrafast"})
    assert path.stat().st_size < 1 << 20
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert lio.read(path)[0].shape == (6, 8, 3)
    with pytest.raises(lio.FormatError, match="4096 x 4096 pixels .* decompression bomb"):
        lio.read(f"{path}:1")


class _Image:
    def __init__(self, info):
        self.info, self.size = info, (8, 6)


class _File(list):
    primary_index = 0


def test_depth_images_gain_maps_and_other_auxiliary_images_are_named_and_ignored(tmp_path):
    """pillow-heif lists them in ``info`` (``depth_images``; ``aux`` by libheif's auxiliary type: Apple's HDR
    gain map is ``urn:com:apple:photo:2020:aux:hdrgainmap``, its portrait matte
    ``urn:com:apple:photo:2018:aux:portraiteffectsmatte``); the encoder here cannot write them, so the listing is
    given as pillow-heif gives it for an iPhone photo."""
    from lenslab.io.heif import _notes
    from lenslab.io.ldr import GainMapWarning

    info = {"depth_images": [object()], "thumbnails": [1],
            "aux": {"urn:com:apple:photo:2020:aux:hdrgainmap": [51],
                    "urn:com:apple:photo:2018:aux:portraiteffectsmatte": [52]}}
    attributes: dict = {}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _notes(tmp_path / "iphone.heic", _File([_Image(info)]), 0, None, info, attributes, raw=False)
    assert attributes["depth"] == "1 depth image(s) present and ignored"
    assert "hdrgainmap" in attributes["gain_map"] and "ignored" in attributes["gain_map"]
    assert attributes["auxiliary"] == ("auxiliary image(s) present and ignored: "
                                       "urn:com:apple:photo:2018:aux:portraiteffectsmatte")
    assert [w.category for w in caught] == [GainMapWarning]
