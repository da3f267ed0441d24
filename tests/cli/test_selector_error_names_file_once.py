"""A selector that picks nothing (``FILE.exr:5``, ``photo.heic:3``): the one error line names the file once,
as the typed selector followed by the reason, not the selector and then the file's path a second time."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main


def test_missing_exr_part_names_the_file_once(tmp_path, capsys):
    import OpenEXR

    path = tmp_path / "one.exr"
    OpenEXR.File({"type": OpenEXR.scanlineimage}, {"RGB": np.zeros((4, 8, 3), np.float32)}).write(str(path))
    assert main(["convert", f"{path}:5", "-o", str(tmp_path / "x.png")]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].count(str(path)) == 1, lines
    assert lines[0].startswith(f"lenslab convert: error: {path}:5: ") and "part 5" in lines[0], lines


def test_missing_file_with_a_selector_keeps_its_path_said(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["convert", "nosuch.exr:1", "-o", "x.png"]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lenslab convert: error: nosuch.exr:1: "), lines
    assert lines[0].endswith("no such file or directory"), lines
