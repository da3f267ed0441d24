"""An EXR whose own values are negative (OpenEXR's WideColorGamut.exr) written as Radiance HDR by ``convert``
or ``warp``: RGBE holds no negative values, so they are set to 0, and the command says so as a display output
(PNG) says it for the same file: the count of values, the lowest, naming the file.

Outside values: the file's values read by OpenEXR's own binding, taken from its chromaticities to BT.709 with
colour-science's matrix in float64 (its primaries are Rec.709's: the matrix is the identity within 1e-7 and
no value changes sign), and the negatives counted with NumPy: 79,397 R, 29,973 G, 18,914 B.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main

colour = pytest.importorskip("colour")
OpenEXR = pytest.importorskip("OpenEXR")

NAME = "formats/openexr-images/TestImages/WideColorGamut.exr"


@pytest.fixture
def exr_file(shared_data) -> Path:
    return shared_data / NAME


@pytest.fixture
def expected(exr_file) -> tuple[int, float, int]:
    exr = OpenEXR.File(str(exr_file))
    values = exr.channels()["RGB"].pixels.astype(np.float64)
    xy = np.asarray(exr.header()["chromaticities"], np.float64).reshape(4, 2)
    matrix = colour.matrix_RGB_to_RGB(colour.RGB_Colourspace("file", xy[:3], xy[3]),
                                      colour.RGB_COLOURSPACES["ITU-R BT.709"], None)
    linear = values @ matrix.T
    assert (np.count_nonzero(values < 0, axis=(0, 1)) == [79397, 29973, 18914]).all()
    return int(np.count_nonzero(linear < 0)), float(linear.min()), linear.size


def _note(err: str) -> list[str]:
    return [line for line in err.splitlines() if "negative" in line]


@pytest.mark.parametrize("command", [["convert", "--to", "hdr"],
                                     ["warp", "--from", "equirect", "--to", "equirect", "--size", "800x800",
                                      "--filter", "nearest"]])
def test_negatives_written_as_rgbe_are_said(tmp_path, capsys, exr_file, expected, command):
    count, lowest, total = expected
    out = tmp_path / "out.hdr"
    assert main([command[0], str(exr_file), *command[1:], "-o", str(out)]) == 0
    assert _note(capsys.readouterr().err) == [
        f"lenslab {command[0]}: note: {exr_file}: Radiance HDR holds no negative values: {count} negative values, down "
        f"to {lowest:.2g}, set to 0 (of {total} values)"]
    assert main(["convert", str(exr_file), "--to", "png", "-o", str(tmp_path / "out.png")]) == 0  # a display output
    assert f"{count} negative values, down to {lowest:.2g}, set to 0 (of {total} values)" in capsys.readouterr().err
