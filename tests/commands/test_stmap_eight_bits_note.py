"""An ST map converted to 8-bit samples (JPG, or PNG/PPM/TIFF with --bits 8) places each source position only to
1/255 of the source's size: ``lenslab convert`` says so in one note, with the source width the map's header
records (256 here, so steps of 256 / 255 = 1.0 pixel) and the 16-bit or EXR way to keep it; at 16 bits, no note.
The width is the one the test gives ``lenslab stmap``; the step is that width over 255."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main


@pytest.fixture
def st_map(tmp_path):
    path = tmp_path / "st.exr"
    assert main(["stmap", "-o", str(path), "--from", "equirect", "--to", "fisheye:fov=180", "--size", "32x32",
                 "--source-size", "256x128", "-q"]) == 0
    return path


@pytest.mark.parametrize("out, extra", [("st.jpg", []), ("st8.png", ["--bits", "8"])])
def test_eight_bits_are_said(tmp_path, capsys, st_map, out, extra):
    capsys.readouterr()
    assert main(["convert", str(st_map), "-o", str(tmp_path / out), *extra]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "ST map" in line]
    assert len(notes) == 1, notes
    assert "1/255" in notes[0] and f"{256 / 255:.2g} pixel" in notes[0], notes[0]


def test_sixteen_bits_are_not(tmp_path, capsys, st_map):
    capsys.readouterr()
    assert main(["convert", str(st_map), "-o", str(tmp_path / "st.png")]) == 0
    assert "ST map" not in capsys.readouterr().err
