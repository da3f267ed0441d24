"""``lenslab convert`` of an ST map that ``lenslab stmap`` wrote to a format without alpha (PPM, PFM, Radiance HDR,
JPG) says that the map's A is dropped and how many of its pixels see nothing of the source (they would read the
source's corner once the map has no A); the count is OpenImageIO's of the EXR map's A = 0, and the written file's
channels are OpenCV's / OpenImageIO's reading. A PNG keeps A and says nothing of it."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")


def _map(tmp_path):
    """A perspective view of 60 degrees placed in a 120-degree fisheye: the fisheye's rim sees nothing of it."""
    path = tmp_path / "st.exr"
    assert main(["stmap", "--from", "perspective:fov=60", "--source-size", "48x36", "--to", "fisheye:fov=120",
                 "--size", "40x40", "-o", str(path), "-q"]) == 0
    a = oiio.ImageBuf(str(path)).get_pixels(oiio.FLOAT)[..., 3]
    return path, int((a == 0).sum()), a.size


@pytest.mark.parametrize("ext, channels", [("ppm", 3), ("pfm", 3), ("hdr", 3)])
def test_a_format_without_alpha_says_the_map_loses_its_validity(tmp_path, capsys, ext, channels):
    st, blind, total = _map(tmp_path)
    assert 0 < blind < total
    out = tmp_path / f"st.{ext}"
    assert main(["convert", str(st), "-o", str(out), "-q"]) == 0
    assert oiio.ImageBuf(str(out)).spec().nchannels == channels  # the file holds no A
    err = capsys.readouterr().err
    assert "keeps no alpha: the ST map's A channel" in err, err
    assert f"its {blind} of {total} pixels that see nothing" in err, err


def test_png_keeps_a_and_says_nothing_of_it(tmp_path, capsys):
    st, blind, _ = _map(tmp_path)
    out = tmp_path / "st.png"
    assert main(["convert", str(st), "-o", str(out), "-q"]) == 0
    a = oiio.ImageBuf(str(out)).get_pixels(oiio.FLOAT)[..., 3]
    assert int((a == 0).sum()) == blind
    assert "keeps no alpha" not in capsys.readouterr().err


def test_the_8bit_note_no_longer_offers_ppm(tmp_path, capsys):
    """PPM keeps 16-bit codes but no A: the 8-bit note names only the formats that keep both."""
    st, _, _ = _map(tmp_path)
    assert main(["convert", str(st), "-o", str(tmp_path / "st8.png"), "--bits", "8", "-q"]) == 0
    err = capsys.readouterr().err
    assert "1/255" in err and "PPM" not in err, err
    assert np.isfinite(oiio.ImageBuf(str(tmp_path / "st8.png")).get_pixels(oiio.FLOAT)).all()


def test_a_jpg_says_both_losses_in_one_note(tmp_path, capsys):
    st, blind, total = _map(tmp_path)
    assert main(["convert", str(st), "-o", str(tmp_path / "st.jpg"), "-q"]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "ST map" in line]
    assert len(notes) == 1 and "1/255" in notes[0] and f"its {blind} of {total} pixels" in notes[0], notes
