"""A TIFF output that tifffile writes as BigTIFF keeps the photo's camera EXIF. tifffile switches to BigTIFF by
itself for more than 4 GB less 32 MB of samples (a 24000 x 15000 float RGB panorama: ``lenslab convert huge.jpg -o
huge.tif`` of a JPEG with EXIF stopped with "an Exif IFD is written into little-endian classic TIFF only", after the
whole image was encoded, and wrote nothing). Here tifffile is asked for BigTIFF at a small size, as it picks it for a
large one.

The outside values: tifffile's reading of the page's ExifTag (the Exif IFD it finds through the pointer), exiftool's
and OpenImageIO's readings of Make, FocalLength and ExposureTime, and the pixels tifffile reads back."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from tests.exif.exif_tools import exiftool, needs_exiftool, oiio_attribute

tifffile = pytest.importorskip("tifffile")

TAGS = {"Make": "Acme", "Model": "Giga Pan", "FocalLength": Fraction(681, 100), "ExposureTime": Fraction(1, 250),
        "FocalLengthIn35mmFilm": 24, "PixelXDimension": 24, "PixelYDimension": 16, "Orientation": 1}


@pytest.fixture
def bigtiff(monkeypatch):
    """tifffile writes BigTIFF, as it does for more than 4 GB of samples."""
    imwrite = tifffile.imwrite
    monkeypatch.setattr(tifffile, "imwrite", lambda *args, **kwargs: imwrite(*args, bigtiff=True, **kwargs))


@pytest.mark.parametrize("sample_type", ["float", "uint16"])
def test_a_bigtiff_output_keeps_its_camera_tags(tmp_path, bigtiff, sample_type):
    from lenslab.io import write

    image = np.linspace(0, 1, 16 * 24 * 3, dtype=np.float32).reshape(16, 24, 3)
    out = tmp_path / "big.tif"
    write(out, image, sample_type=sample_type, exif=TAGS)
    with tifffile.TiffFile(out) as tif:
        assert tif.is_bigtiff and len(tif.pages) == 1
        page = tif.pages[0]
        assert (page.tags["Make"].value, page.tags["Model"].value) == ("Acme", "Giga Pan")
        exif = page.tags["ExifTag"].value
        assert exif["FocalLength"] == (681, 100) and exif["ExposureTime"] == (1, 250)
        assert exif["FocalLengthIn35mmFilm"] == 24
        back = page.asarray()
    expected = image if sample_type == "float" else None
    if expected is not None:
        np.testing.assert_array_equal(back, expected)
    else:
        assert back.shape == (16, 24, 3) and back.dtype == np.uint16
    assert oiio_attribute(out, "Exif:FocalLength") == pytest.approx(6.81, abs=1e-6)  # (OpenImageIO's float)
    assert oiio_attribute(out, "Make") == "Acme"


@needs_exiftool
def test_exiftool_reads_a_bigtiff_output_s_exif(tmp_path, bigtiff):
    from lenslab.io import write

    out = tmp_path / "big.tif"
    write(out, np.full((16, 24, 3), 0.5, np.float32), exif=TAGS)
    tags = exiftool(out, "Make", "Model", "FocalLength", "ExposureTime", "FocalLengthIn35mmFormat", "Orientation")
    assert tags == {"SourceFile": str(out), "Make": "Acme", "Model": "Giga Pan", "FocalLength": 6.81,
                    "ExposureTime": 0.004, "FocalLengthIn35mmFormat": 24, "Orientation": 1}


@needs_exiftool
def test_a_bigtiff_photo_s_exif_goes_with_its_copy(tmp_path, capsys, bigtiff):
    """A BigTIFF's own IFDs (and its Exif IFD) are read as a classic TIFF's: its camera reaches a JPEG made of it
    (it was left behind without a word)."""
    from lenslab.io import write
    from tests.exif.exif_tools import run

    source = tmp_path / "big.tif"
    write(source, np.full((16, 24, 3), 0.5, np.float32), exif=TAGS)
    assert tifffile.TiffFile(source).is_bigtiff
    code, err = run(capsys, "convert", source, "-o", tmp_path / "copy.jpg", "-q")
    assert code == 0, err
    tags = exiftool(tmp_path / "copy.jpg", "Make", "Model", "FocalLength", "ExposureTime", "FocalLengthIn35mmFormat")
    assert tags == {"SourceFile": str(tmp_path / "copy.jpg"), "Make": "Acme", "Model": "Giga Pan", "FocalLength": 6.81,
                    "ExposureTime": 0.004, "FocalLengthIn35mmFormat": 24}
