"""``convert --tone`` to a float TIFF is refused (a float TIFF keeps linear light), and the one line says
what a TIFF takes a curve with: ``--bits 8`` or ``16``, display codes, which ``convert --help`` promises."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main


def test_tone_to_float_tiff_names_bits(tmp_path, capsys):
    import lenslab

    src = tmp_path / "a.exr"
    lenslab.write(src, np.full((4, 8, 3), 2.0, np.float32))
    assert main(["convert", str(src), "-o", str(tmp_path / "a.tif"), "--tone", "aces"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "--tone applies to display formats" in lines[0] and "--bits" in lines[0], lines
    assert main(["convert", str(src), "-o", str(tmp_path / "b.tif"), "--tone", "aces", "--bits", "8"]) == 0
