"""``--pixel-type half`` or ``float`` with ``--bits 8|16`` asks for float samples and integer ones at once: a usage
error (exit 2, the brief's code for usage) in one line naming both, before any file is written, as ``--pixel-type
uint16 --bits 8`` is; it wrote the integers ``--bits`` asked for and dropped the float type without a word.
A depth both name alike is written (tifffile reads the samples: 16-bit unsigned integers)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

tifffile = pytest.importorskip("tifffile")


def _source(tmp_path):
    y, x = np.mgrid[0:8, 0:12].astype(np.float32)
    path = tmp_path / "src.exr"
    write(path, np.stack([x / 12, y / 8, (x + y) / 20], axis=-1), pixel_type="float")
    return path


@pytest.mark.parametrize("ext", ["tiff", "exr"])
@pytest.mark.parametrize("pixel_type, bits", [("float", "8"), ("half", "16")])
def test_a_float_pixel_type_with_bits_is_refused(tmp_path, capsys, ext, pixel_type, bits):
    out = tmp_path / f"out.{ext}"
    code = main(["convert", str(_source(tmp_path)), "-o", str(out), "--pixel-type", pixel_type, "--bits", bits])
    err = capsys.readouterr().err
    assert code == 2, err
    assert f"--pixel-type {pixel_type}" in err and f"--bits {bits}" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_an_integer_pixel_type_of_the_bits_depth_is_written(tmp_path):
    out = tmp_path / "out.tiff"
    assert main(["convert", str(_source(tmp_path)), "-o", str(out), "--pixel-type", "uint16", "--bits", "16"]) == 0
    assert tifffile.imread(out).dtype == np.uint16
