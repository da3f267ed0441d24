"""A wide-gamut file (Display P3, Adobe RGB; a PNG with an ICC profile or a cICP chunk, a JPEG, a TIFF) written
as an sRGB PNG or JPEG by ``convert`` or ``tonemap``: its colours outside the sRGB gamut are clipped per
channel, and the command says so once, in those words, with the count of pixels; never as repaired damage or
a codec's undershoot.

Outside values: which pixels lie outside the sRGB gamut is colour-science's answer in float64 (its sRGB or
Adobe RGB decoding and its matrix from the file's primaries to BT.709: a negative component is a chromaticity
outside the BT.709 triangle); pixels within 2e-3 of the gamut's edge are made grey, so that the count does not
depend on the last bits of float32 (lenslab's colorants come from the profile, whose s15.16 numbers and
chromatic adaptation move a component by about 1e-4). The clipped codes of the PNG are littleCMS's (Pillow's
ImageCms, the file's profile to its built-in sRGB, relative colorimetric, 8-bit: per-channel clipping, as a
colour-managed viewer shows the file) within one code (its 1.14 fixed-point pipeline, see
``tests/io/test_icc_profiles.py``).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main

colour = pytest.importorskip("colour")
ImageCms = pytest.importorskip("PIL.ImageCms")
from PIL import Image  # noqa: E402

from lenslab.io.colour.icc_build import profile as build_profile  # noqa: E402
from lenslab.io.colour.icc_chunks import png_with_profile  # noqa: E402
from lenslab.io.colour.png_cicp import with_cicp  # noqa: E402

GHOSTSCRIPT = Path("/usr/share/color/icc/ghostscript")  # Debian's libgs-common, which .ci/run installs
EDGE = 2e-3  # linear light: pixels this close to the gamut's edge are replaced by grey (see the docstring)
SPACES = {"display-p3": "Display P3", "a98": "Adobe RGB (1998)", "cicp-p3": "Display P3"}


def _icc(name: str) -> bytes | None:
    if name == "display-p3":
        return build_profile("Display P3")
    if name == "a98":
        path = GHOSTSCRIPT / "a98.icc"
        if not path.is_file():
            pytest.skip(f"{path} is absent (Debian's libgs-common, which .ci/run installs)")
        return path.read_bytes()
    return None


def _linear_709(codes: np.ndarray, name: str) -> np.ndarray:
    """colour-science's linear BT.709 of ``codes`` read on the primaries and curve of ``name``."""
    return colour.RGB_to_RGB(codes.astype(np.float64) / 255, SPACES[name], "ITU-R BT.709", None,
                             apply_cctf_decoding=True)


def _codes(name: str) -> np.ndarray:
    codes = np.random.default_rng(7).integers(0, 256, (40, 56, 3), dtype=np.uint8)
    codes[0, :4] = [[255, 0, 0], [0, 255, 0], [40, 200, 60], [128, 128, 128]]
    low = _linear_709(codes, name).min(axis=-1)
    codes[np.abs(low) < EDGE] = 128  # near the edge: grey, well inside
    return codes


def _write(path: Path, codes: np.ndarray, name: str) -> None:
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")  # Pillow writes the file: lenslab only reads it
    data = buf.getvalue()
    icc = _icc(name)
    path.write_bytes(png_with_profile(data, icc) if icc is not None else with_cicp(data, (12, 13, 0, 1)))


def _littlecms(codes: np.ndarray, icc: bytes) -> np.ndarray:
    t = ImageCms.buildTransform(ImageCms.ImageCmsProfile(io.BytesIO(icc)), ImageCms.createProfile("sRGB"), "RGB",
                                "RGB", ImageCms.Intent.RELATIVE_COLORIMETRIC)
    return np.asarray(ImageCms.applyTransform(Image.fromarray(codes), t)).astype(np.float64)


def _notes(err: str) -> list[str]:  # (tonemap's note on a display source is tests/tone/test_tonemap_display_source_note.py's)
    return [line for line in err.splitlines() if "note:" in line and "holds display values already" not in line]


@pytest.mark.parametrize("name", sorted(SPACES))
@pytest.mark.parametrize("command", ["convert", "tonemap", "compare-tones"])
@pytest.mark.parametrize("ext", ["png", "jpg"])
def test_colours_outside_srgb_are_counted_and_called_clipped(tmp_path, capsys, name, command, ext):
    codes = _codes(name)
    outside = int((_linear_709(codes, name).min(axis=-1) < 0).sum())
    assert 0 < outside < codes.shape[0] * codes.shape[1]  # the image has colours of both kinds
    src, out = tmp_path / "wide.png", tmp_path / f"out.{ext}"
    _write(src, codes, name)
    args = ["convert", str(src), "--to", ext, "-o", str(out)] if command == "convert" else \
        [command, str(src), "-o", str(out)]
    assert main(args) == 0
    err = capsys.readouterr().err
    given = {"display-p3": "ICC profile 'Display P3'", "a98": "ICC profile 'Artifex Software A98 ICC Profile'",
             "cicp-p3": "cICP primaries P3-D65"}[name]  # the profile's own description, or the chunk's code
    want = (f"lenslab {command}: note: {src}: {outside} of {codes.shape[0] * codes.shape[1]} pixels hold colours "
            f"outside the sRGB gamut (the file's {given}): clipped per channel")
    assert _notes(err) == [want], err
    assert "undershoot" not in err and "repaired" not in err, err


@pytest.mark.parametrize("name", ["display-p3", "a98"])
def test_the_clipped_png_is_what_littlecms_shows(tmp_path, name):
    codes = _codes(name)
    src, out = tmp_path / "wide.png", tmp_path / "out.png"
    _write(src, codes, name)
    assert main(["convert", str(src), "--to", "png", "-o", str(out)]) == 0
    ours = np.asarray(Image.open(out).convert("RGB")).astype(np.float64)
    np.testing.assert_allclose(ours, _littlecms(codes, _icc(name)), rtol=0, atol=1.0)


def test_an_srgb_file_and_an_hdr_output_say_nothing(tmp_path, capsys):
    """Nothing is clipped where the file is sRGB, or where the output keeps the negative components (EXR)."""
    codes = _codes("display-p3")
    plain, wide = tmp_path / "plain.png", tmp_path / "wide.png"
    Image.fromarray(codes).save(plain)
    _write(wide, codes, "display-p3")
    assert main(["convert", str(plain), "--to", "png", "-o", str(tmp_path / "plain-out.png")]) == 0
    assert main(["convert", str(wide), "--to", "exr", "-o", str(tmp_path / "wide.exr")]) == 0
    assert _notes(capsys.readouterr().err) == []


@pytest.mark.parametrize("fmt", ["jpg", "tif"])
def test_a_jpeg_or_tiff_with_a_profile_says_it_too(tmp_path, capsys, fmt):
    """The profile in a JPEG's APP2 segments (written by Pillow) or a TIFF's tag 34675 (by tifffile). The JPEG
    holds flat 8 x 8 blocks at quality 100 without chroma subsampling; the count is made from the codes its
    decoder gives (lenslab's raw reading, the codes before any colour management)."""
    from lenslab.io import read

    icc = _icc("display-p3")
    codes = np.kron(_codes("display-p3")[:5, :7], np.ones((8, 8, 1), np.uint8))
    src = tmp_path / f"wide.{fmt}"
    if fmt == "jpg":
        Image.fromarray(codes).save(src, "JPEG", quality=100, subsampling=0, icc_profile=icc)
        codes = np.rint(read(src, raw=True)[0] * 255).astype(np.uint8)
    else:
        import tifffile

        tifffile.imwrite(src, codes, photometric="rgb", iccprofile=icc)
    low = _linear_709(codes, "display-p3").min(axis=-1)
    assert np.abs(low).min() > 1e-4  # no pixel at the gamut's edge: the count is the same in float32
    outside = int((low < 0).sum())
    assert 0 < outside < low.size
    assert main(["tonemap", str(src), "-o", str(tmp_path / "out.png")]) == 0
    err = capsys.readouterr().err
    assert _notes(err) == [f"lenslab tonemap: note: {src}: {outside} of {low.size} pixels hold colours outside the "
                           "sRGB gamut (the file's ICC profile 'Display P3'): clipped per channel"], err


def _p3_linear(name: str = "display-p3") -> np.ndarray:
    """float32 linear light on Display P3 primaries (colour-science's sRGB decoding of :func:`_codes`)."""
    return colour.cctf_decoding(_codes(name).astype(np.float64) / 255, "sRGB").astype(np.float32)


def _exr_with_p3_chromaticities(path: Path, values: np.ndarray) -> None:
    """Written by OpenImageIO, with the chromaticities attribute of colour-science's Display P3."""
    oiio = pytest.importorskip("OpenImageIO")
    space = colour.RGB_COLOURSPACES["Display P3"]
    spec = oiio.ImageSpec(values.shape[1], values.shape[0], 3, "float")
    spec.attribute("chromaticities", oiio.TypeDesc("float[8]"),
                   tuple(float(v) for v in [*space.primaries.reshape(-1), *space.whitepoint]))
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec) and out.write_image(values), oiio.geterror()
    out.close()


@pytest.mark.parametrize("fmt", ["exr", "float tiff"])
def test_a_float_file_without_negatives_of_its_own_says_it_too(tmp_path, capsys, fmt):
    """An EXR on P3 chromaticities, or a float TIFF with a linear P3 profile: the file holds no negative, so the
    negatives after the conversion are colours outside the gamut (counted on colour-science's matrix)."""
    values = _p3_linear()
    src = tmp_path / ("wide.exr" if fmt == "exr" else "wide.tif")
    if fmt == "exr":
        _exr_with_p3_chromaticities(src, values)
        given = "chromaticities"
    else:
        import tifffile

        from tests.io.test_icc_profiles import _para  # lenslab's P3 profile with a linear para curve

        tifffile.imwrite(src, values, photometric="rgb", iccprofile=_para(0, [1.0]))
        given = "ICC profile 'Display P3'"
    low = colour.RGB_to_RGB(values.astype(np.float64), "Display P3", "ITU-R BT.709", None).min(axis=-1)
    outside = int((low < 0).sum())
    assert main(["tonemap", str(src), "-o", str(tmp_path / "out.png")]) == 0
    err = capsys.readouterr().err
    assert _notes(err) == [f"lenslab tonemap: note: {src}: {outside} of {low.size} pixels hold colours outside the "
                           f"sRGB gamut (the file's {given}): clipped per channel"], err


def test_a_float_file_with_negatives_of_its_own_keeps_the_repair_note(tmp_path, capsys):
    """One value of the file's own below 0: its negatives cannot be told from the gamut's, and tone mapping
    reports them as it reports any negative."""
    values = _p3_linear()
    values[5, 5, 1] = -0.25
    src = tmp_path / "own.exr"
    _exr_with_p3_chromaticities(src, values)
    assert main(["tonemap", str(src), "-o", str(tmp_path / "out.png")]) == 0
    err = capsys.readouterr().err
    assert "outside the sRGB gamut" not in err and "negative values" in err, err
