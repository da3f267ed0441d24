"""Embedded ICC profiles mean what they say: read through littleCMS's answer, written as colour-science's P3.

Expected values come from outside lenslab: littleCMS (Pillow's ``ImageCms.buildTransform`` from the file's
profile to its built-in sRGB, 8-bit, relative colorimetric) on the same code values; colour-science's sRGB
curve and its P3-D65 -> BT.709 matrix in float64; colour-science's Display P3 primaries adapted to D50 by
Bradford against the colorants littleCMS parses from the written profile; Pillow's own reading of the files.

Tolerances: against littleCMS, 1 code of 8 bits: its output is rounded to a code (0.5) and its 8-bit
matrix-shaper pipeline works in 1.14 fixed point with 16-bit curve tables (measured under 0.65 for Display P3,
Adobe RGB and ROMM); against colour-science, 2e-5 of linear light: the written colorants are s15.16 numbers
(2^-17 = 7.6e-6 each) and the para curve's parameters too (4.2e-6 from IEC 61966-2-1's curve).
"""

from __future__ import annotations

import io
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.errors import FormatError

colour = pytest.importorskip("colour")
ImageCms = pytest.importorskip("PIL.ImageCms")
from PIL import Image  # noqa: E402

import lenslab.io as lio  # noqa: E402
from lenslab.io.colour.icc_build import profile as build_profile  # noqa: E402
from lenslab.io.colour.icc_chunks import jpeg_with_profile, png_with_profile  # noqa: E402
from lenslab.io.colour.png_cicp import with_cicp  # noqa: E402

GHOSTSCRIPT = Path("/usr/share/color/icc/ghostscript")  # Debian's libgs-common
SRGB_ENCODE = lambda x: colour.cctf_encoding(np.clip(x, 0, 1), "sRGB")  # noqa: E731
P3_TO_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["Display P3"], colour.RGB_COLOURSPACES["ITU-R BT.709"])


def _system(name: str) -> bytes:
    path = GHOSTSCRIPT / name
    if not path.is_file():
        pytest.skip(f"{path} is absent (Debian's libgs-common, which .ci/run installs)")
    return path.read_bytes()


def _codes(shape=(48, 64, 3), seed=0) -> np.ndarray:
    codes = np.random.default_rng(seed).integers(0, 256, shape, dtype=np.uint8)
    codes[0, :8] = [[0, 0, 0], [255, 255, 255], [255, 0, 0], [0, 255, 0], [0, 0, 255], [128, 128, 128],
                    [1, 1, 1], [254, 254, 254]]
    return codes


def _png(codes: np.ndarray, icc: bytes | None = None, cicp=None) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")  # Pillow writes the file: lenslab only reads it
    data = buf.getvalue()
    data = with_cicp(data, cicp) if cicp else data
    return png_with_profile(data, icc) if icc is not None else data


def _littlecms(codes: np.ndarray, icc: bytes) -> np.ndarray:
    """littleCMS's sRGB codes of ``codes`` under profile ``icc``."""
    t = ImageCms.buildTransform(ImageCms.ImageCmsProfile(io.BytesIO(icc)), ImageCms.createProfile("sRGB"), "RGB",
                                "RGB", ImageCms.Intent.RELATIVE_COLORIMETRIC)  # (perceptual: v4 black point comp.)
    return np.asarray(ImageCms.applyTransform(Image.fromarray(codes), t)).astype(np.float64)


def _read_as_srgb(path) -> tuple[np.ndarray, dict]:
    img, meta = lio.read(path)
    return SRGB_ENCODE(img[..., :3].astype(np.float64)) * 255.0, meta


@pytest.mark.parametrize("name", ["a98.icc", "rommrgb.icc", "display-p3"])
@pytest.mark.parametrize("fmt", ["png", "tiff"])
def test_matrix_trc_profiles_read_as_littlecms_converts_them(tmp_path, name, fmt):
    icc = build_profile("Display P3") if name == "display-p3" else _system(name)
    codes = _codes()
    path = tmp_path / f"in.{fmt}"
    if fmt == "png":
        path.write_bytes(_png(codes, icc))
    else:
        import tifffile

        tifffile.imwrite(path, codes, photometric="rgb", iccprofile=icc)  # tag 34675, written by tifffile
    ours, meta = _read_as_srgb(path)
    assert "applied" in meta["attributes"]["icc"] and "not applied" not in meta["attributes"]["icc"]
    np.testing.assert_allclose(ours, _littlecms(codes, icc), rtol=0, atol=1.0)


def test_a_real_display_p3_photo_reads_as_littlecms_converts_it(shared_data):
    """The Ultra HDR sample's SDR image carries a phone's Display P3 profile (v4, para type 3, chad)."""
    path = shared_data / "formats/oiio-images/ultrahdr_sky.jpg"
    with Image.open(path) as im:
        icc = im.info["icc_profile"]
    raw, _ = lio.read(path, raw=True)  # the decoder's code values, given to littleCMS too
    codes = np.round(raw * 255).astype(np.uint8)[::7, ::7]
    ours, meta = _read_as_srgb(f"{path}:sdr")  # the SDR base image (the default read applies the gain map)
    assert "'Display P3'" in meta["attributes"]["icc"]
    np.testing.assert_allclose(ours[::7, ::7], _littlecms(codes, icc), rtol=0, atol=1.0)


def test_the_written_p3_profile_is_colour_sciences_p3_adapted_to_d50():
    space = colour.RGB_COLOURSPACES["Display P3"]
    d50 = np.array([0.9642, 1.0, 0.8249])  # ICC.1 7.2.16
    chad = colour.adaptation.matrix_chromatic_adaptation_VonKries(colour.xy_to_XYZ(space.whitepoint), d50, "Bradford")
    want = chad @ colour.normalised_primary_matrix(space.primaries, space.whitepoint)
    parsed = ImageCms.ImageCmsProfile(io.BytesIO(build_profile("Display P3")))
    got = np.array([getattr(parsed.profile, f"{c}_colorant")[0] for c in ("red", "green", "blue")]).T
    np.testing.assert_allclose(got, want, rtol=0, atol=2.0 ** -16)  # s15.16 rounding
    np.testing.assert_allclose(np.array(parsed.profile.chromatic_adaptation[0]), chad, rtol=0, atol=2.0 ** -16)
    assert ImageCms.getProfileDescription(parsed).strip() == "Display P3"
    assert parsed.profile.is_matrix_shaper and parsed.profile.version == 4.4


def test_p3_codes_read_as_colour_sciences_matrix_on_linear_values(tmp_path):
    codes = np.random.default_rng(2).integers(0, 65536, (40, 50, 3), dtype=np.uint16)
    import tifffile

    tifffile.imwrite(tmp_path / "p3.tif", codes, photometric="rgb", iccprofile=build_profile("Display P3"))
    got, _ = lio.read(tmp_path / "p3.tif")
    want = colour.cctf_decoding(codes / 65535.0, "sRGB") @ P3_TO_709.T
    np.testing.assert_allclose(got, want, rtol=0, atol=2e-5)


def test_display_p3_output_carries_an_icc_profile_beside_cicp(tmp_path):
    """A Display P3 PNG as Pillow sees it (no cICP): littleCMS's reading of its profile is lenslab's reading
    of its cICP chunk; the TIFF's tag 34675 the same."""
    pytest.importorskip("PyOpenColorIO")
    from lenslab.io.colour.png_cicp import read_cicp

    scene = np.random.default_rng(3).random((24, 32, 3), dtype=np.float32)
    lio.write(tmp_path / "s.exr", scene, pixel_type="float")
    from lenslab.cli.main import main

    for fmt in ("png", "tiff"):
        assert main(["convert", str(tmp_path / "s.exr"), "--to", fmt, "--display", "Display P3 - Display",
                     "--bits", "8", "-o", str(tmp_path / f"p3.{fmt[:3]}")]) in (0, None)
    data = (tmp_path / "p3.png").read_bytes()
    assert read_cicp(data) == (12, 13, 0, 1)
    with Image.open(tmp_path / "p3.png") as im:
        icc, codes = im.info["icc_profile"], np.asarray(im.convert("RGB"))
    ours, meta = _read_as_srgb(tmp_path / "p3.png")
    assert "precedence" in meta["attributes"]["icc"]
    np.testing.assert_allclose(ours, _littlecms(codes, icc), rtol=0, atol=1.0)
    tif, meta = _read_as_srgb(tmp_path / "p3.tif")
    assert "'Display P3'" in meta["attributes"]["icc"]
    # the profile's s15.16 colorants (within 1e-5 of colour-science's matrix) against cICP's exact matrix: under
    # 12.92 * 255 * 1e-5 = 0.033 of a code after sRGB encoding, its steepest
    np.testing.assert_allclose(tif, ours, rtol=0, atol=0.05)


def test_cicp_wins_over_iccp(tmp_path):
    codes = _codes()
    (tmp_path / "t.png").write_bytes(_png(codes, build_profile("Display P3"), cicp=(1, 13, 0, 1)))
    img, meta = lio.read(tmp_path / "t.png")
    np.testing.assert_allclose(img, colour.cctf_decoding(codes / 255.0, "sRGB"), rtol=0, atol=1e-6)
    assert "cICP chunk takes precedence" in meta["attributes"]["icc"]


def test_srgb_profiles_read_as_today_and_others_are_noted(tmp_path):
    codes = _codes()
    (tmp_path / "plain.png").write_bytes(_png(codes))
    plain, _ = lio.read(tmp_path / "plain.png")
    np.testing.assert_allclose(plain, colour.cctf_decoding(codes / 255.0, "sRGB"), rtol=0, atol=1e-6)
    lcms_srgb = ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()  # littleCMS's own, v4 para
    lab = ImageCms.ImageCmsProfile(ImageCms.createProfile("LAB")).tobytes()
    for icc, says in ((lcms_srgb, "sRGB, read as sRGB"), (lab, "not applied, read as sRGB")):
        (tmp_path / "t.png").write_bytes(_png(codes, icc))
        img, meta = lio.read(tmp_path / "t.png")
        np.testing.assert_array_equal(img, plain)
        assert says in meta["attributes"]["icc"]
    if (GHOSTSCRIPT / "default_cmyk.icc").is_file():
        (tmp_path / "c.jpg").write_bytes(jpeg_with_profile(_jpeg(codes), _system("default_cmyk.icc")))
        img, meta = lio.read(tmp_path / "c.jpg")
        assert "CMYK" in meta["attributes"]["icc"] and "not applied" in meta["attributes"]["icc"]


def _jpeg(codes: np.ndarray) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "JPEG", quality=95)
    return buf.getvalue()


def test_a_jpeg_profile_in_app2_segments_is_applied(tmp_path):
    codes = _codes()
    icc = _system("a98.icc")
    (tmp_path / "a.jpg").write_bytes(jpeg_with_profile(_jpeg(codes), icc))
    with Image.open(tmp_path / "a.jpg") as im:
        assert im.info["icc_profile"] == icc  # Pillow finds what was written
    raw, _ = lio.read(tmp_path / "a.jpg", raw=True)
    ours, _ = _read_as_srgb(tmp_path / "a.jpg")
    np.testing.assert_allclose(ours, _littlecms(np.round(raw * 255).astype(np.uint8), icc), rtol=0, atol=1.0)


def _tag(icc: bytes, sig: bytes) -> int:
    count = struct.unpack(">I", icc[128:132])[0]
    for i in range(count):
        if icc[132 + 12 * i:136 + 12 * i] == sig:
            return 132 + 12 * i
    raise KeyError(sig)


def _hostile() -> dict[str, bytes]:
    good = bytearray(build_profile("Display P3"))
    outside = bytearray(good)
    outside[_tag(good, b"rXYZ") + 4:_tag(good, b"rXYZ") + 8] = struct.pack(">I", 1 << 30)
    longer = bytearray(good)
    longer[:4] = struct.pack(">I", len(good) + 100)
    flat = bytearray(good)
    at = struct.unpack(">I", good[_tag(good, b"rTRC") + 4:_tag(good, b"rTRC") + 8])[0]
    flat[at + 12:at + 16] = bytes(4)  # gamma 0
    return {"outside": bytes(outside), "declares": bytes(longer), "gamma": bytes(flat)}


@pytest.mark.parametrize("case, cause", [("outside", "outside"), ("declares", "declares"), ("gamma", "gamma 0")])
def test_hostile_profiles_are_refused_in_one_line(tmp_path, case, cause):
    (tmp_path / "h.png").write_bytes(_png(_codes((8, 8, 3)), _hostile()[case]))
    with pytest.raises(FormatError) as err:
        lio.read(tmp_path / "h.png")
    message = str(err.value)
    assert "\n" not in message and "h.png" in message and "ICC profile" in message and cause in message


def test_an_iccp_chunk_that_inflates_past_the_budget_is_refused(tmp_path):
    from lenslab.io.colour.png_cicp import png_chunk

    data = _png(_codes((8, 8, 3)))
    bomb = png_chunk(b"iCCP", b"x\0\0" + zlib.compress(bytes(64 << 20), 9))  # 64 MiB in about 64 kB
    (tmp_path / "b.png").write_bytes(data[:33] + bomb + data[33:])
    with pytest.raises(FormatError, match="inflates past"):
        lio.read(tmp_path / "b.png")


def test_a_jpeg_profile_missing_a_segment_is_refused(tmp_path):
    icc = build_profile("Display P3")
    jpg = jpeg_with_profile(_jpeg(_codes((8, 8, 3))), icc)
    at = jpg.index(b"ICC_PROFILE\0") + 12
    jpg = jpg[:at] + bytes([2, 2]) + jpg[at + 2:]  # says segment 2 of 2; segment 1 is nowhere
    (tmp_path / "m.jpg").write_bytes(jpg)
    with pytest.raises(FormatError, match="segments"):
        lio.read(tmp_path / "m.jpg")


def _retagged(icc: bytes, sigs, body: bytes) -> bytes:
    """``icc`` with tags ``sigs`` pointing at ``body``, appended at its end (its size updated)."""
    out = bytearray(icc) + bytes(-len(icc) % 4)
    at = len(out)
    out += body
    for sig in sigs:
        out[_tag(icc, sig) + 4:_tag(icc, sig) + 12] = struct.pack(">II", at, len(body))
    out[:4] = struct.pack(">I", len(out))
    return bytes(out)


def _para(function: int, params) -> bytes:
    """lenslab's Display P3 profile with its curves replaced by one ``para`` curve of ``function``."""
    body = b"para" + bytes(4) + struct.pack(">H", function) + bytes(2)
    body += b"".join(struct.pack(">i", round(v * 65536)) for v in params)
    return _retagged(build_profile("Display P3"), (b"rTRC", b"gTRC", b"bTRC"), body)


def _near(ours: np.ndarray, theirs: np.ndarray) -> None:
    """Within 1 code of littleCMS where its code is 16 or more. Below, littleCMS's 8-bit pipeline (curves joined
    into 16-bit tables, interpolated) strays from the curve where sRGB's slope is 12.92: measured up to 1.47 codes
    for a gamma of 1.8, which the float64 formula of ICC.1 checks instead. (Curves with a jump at ``d`` are left
    out: littleCMS resamples them and interpolates across the jump.)"""
    above = theirs >= 16
    np.testing.assert_allclose(ours[above], theirs[above], rtol=0, atol=1.0)


PARA = {0: lambda x, g: x ** g, 1: lambda x, g, a, b: np.where(x >= -b / a, np.clip(a * x + b, 0, None) ** g, 0.0),
        2: lambda x, g, a, b, c: np.where(x >= -b / a, np.clip(a * x + b, 0, None) ** g + c, c),
        3: lambda x, g, a, b, c, d: np.where(x >= d, np.clip(a * x + b, 0, None) ** g, c * x),
        4: lambda x, g, a, b, c, d, e, f: np.where(x >= d, np.clip(a * x + b, 0, None) ** g + e, c * x + f)}


@pytest.mark.parametrize("function, params", [(0, [1.8]), (1, [2.2, 1.1, -0.1]), (2, [2.0, 0.9, 0.05, 0.02]),
                                              (3, [2.6, 1.0, 0.0, 0.5, 0.1]),
                                              (4, [2.4, 1 / 1.055, 0.055 / 1.055, 1 / 12.92, 0.04045, 0.01, 0.01])])
def test_parametric_curves_read_as_icc1_and_littlecms_evaluate_them(tmp_path, function, params):
    """ICC.1 table 68's five functions transcribed in float64 (parameters rounded to s15.16, output clipped to
    [0, 1]), then colour-science's P3 -> Rec.709 matrix; and littleCMS on the same codes."""
    icc = _para(function, params)
    codes = _codes()
    (tmp_path / "p.png").write_bytes(_png(codes, icc))
    img, _ = lio.read(tmp_path / "p.png")
    q = [round(v * 65536) / 65536 for v in params]
    want = np.clip(PARA[function](codes / 255.0, *q), 0, 1) @ P3_TO_709.T
    np.testing.assert_allclose(img, want, rtol=0, atol=2e-5)
    _near(SRGB_ENCODE(img.astype(np.float64)) * 255, _littlecms(codes, icc))


def test_a_grey_profile_reads_as_its_curve_says(tmp_path):
    """Ghostscript's grey profile with its kTRC made a gamma of 1.8 (curv, u8.8: 461 / 256): the curve in
    float64, and littleCMS's grey -> sRGB on the same codes."""
    icc = _retagged(_system("default_gray.icc"), (b"kTRC",), b"curv" + bytes(4) + struct.pack(">IH", 1, 461))
    codes = _codes((32, 40, 3))[..., 0]
    (tmp_path / "g.png").write_bytes(_png(codes, icc))
    img, meta = lio.read(tmp_path / "g.png")
    assert img.shape == (32, 40, 1) and "grey curve applied" in meta["attributes"]["icc"]
    np.testing.assert_allclose(img[..., 0], (codes / 255.0) ** (461 / 256), rtol=0, atol=1e-6)
    t = ImageCms.buildTransform(ImageCms.ImageCmsProfile(io.BytesIO(icc)), ImageCms.createProfile("sRGB"), "L",
                                "RGB", ImageCms.Intent.RELATIVE_COLORIMETRIC)
    theirs = np.asarray(ImageCms.applyTransform(Image.fromarray(codes), t)).astype(np.float64)[..., 1]
    _near(SRGB_ENCODE(img[..., 0].astype(np.float64)) * 255, theirs)


def test_alpha_stays_coverage_and_16_bit_pngs_are_decoded_through_the_profile(tmp_path):
    """RGBA: the profile acts on the straight colour, then it is premultiplied (colour-science's sRGB curve and
    P3 matrix, to the profile's s15.16 precision); 16-bit: every code through the curve, not a table of 256."""
    import cv2

    codes = np.random.default_rng(5).integers(0, 65536, (24, 30, 4), dtype=np.uint16)

    _, enc = cv2.imencode(".png", codes[..., [2, 1, 0, 3]])  # OpenCV writes 16-bit RGBA (B, G, R, A order)
    (tmp_path / "a.png").write_bytes(png_with_profile(enc.tobytes(), build_profile("Display P3")))
    img, _ = lio.read(tmp_path / "a.png")
    alpha = codes[..., 3:] / 65535.0
    want = (colour.cctf_decoding(codes[..., :3] / 65535.0, "sRGB") @ P3_TO_709.T) * alpha
    np.testing.assert_allclose(img[..., :3], want, rtol=0, atol=2e-5)
    np.testing.assert_allclose(img[..., 3:], alpha, rtol=0, atol=1e-7)


@settings(max_examples=12, deadline=None)
@given(size=st.integers(1, 200_000), seed=st.integers(0, 2 ** 32 - 1))
def test_profiles_of_any_size_are_found_as_pillow_finds_them(size, seed):
    """APP2 segments of 65519 bytes each (a profile of 200 kB takes four) and an iCCP chunk: Pillow's reading of
    the written file is the profile, and so is lenslab's."""
    from lenslab.io.colour.icc_chunks import jpeg_profile, png_profile

    icc = np.random.default_rng(seed).integers(0, 256, size, dtype=np.uint8).tobytes()
    codes = _codes((8, 8, 3))
    for data, find in ((jpeg_with_profile(_jpeg(codes), icc), jpeg_profile), (_png(codes, icc), png_profile)):
        with Image.open(io.BytesIO(data)) as im:
            assert im.info["icc_profile"] == icc
        assert find(data, "f") == icc


def test_float_tiffs_follow_a_linear_profile_and_note_a_curved_one(tmp_path):
    """Float samples are linear light: a linear P3 profile's colorants apply (colour-science's matrix, to the
    profile's s15.16 precision); the sRGB-curved P3 profile is noted, not applied (the samples stay as written)."""
    import tifffile

    values = np.random.default_rng(6).random((16, 20, 3), dtype=np.float32) * 4
    tifffile.imwrite(tmp_path / "lin.tif", values, photometric="rgb", iccprofile=_para(0, [1.0]))
    tifffile.imwrite(tmp_path / "srgb.tif", values, photometric="rgb", iccprofile=build_profile("Display P3"))
    got, meta = lio.read(tmp_path / "lin.tif")
    # the profile's matrix is within 1e-5 of colour-science's in each entry (s15.16 colorants): values up to 4
    # summed over three terms, 1.2e-4
    np.testing.assert_allclose(got, values.astype(np.float64) @ P3_TO_709.T, rtol=0, atol=1.2e-4)
    assert "applied" in meta["attributes"]["icc"]
    got, meta = lio.read(tmp_path / "srgb.tif")
    np.testing.assert_array_equal(got, values)
    assert "not applied" in meta["attributes"]["icc"]
