"""``--tone CURVE`` given for a source that holds display values already (a PNG, JPEG, 8-bit HEIC) written to a
display format: the curve maps HDR scene light and is not applied to it (the PNG's codes come out as they
went in, read back with OpenCV), and the command says so in one note instead of ignoring what was typed;
a batch says it once. Without ``--tone`` nothing is said."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main


@pytest.fixture
def png(tmp_path):
    import cv2

    codes = np.random.default_rng(5).integers(0, 256, (8, 16, 3), dtype=np.uint8)
    path = tmp_path / "photo.png"
    assert cv2.imwrite(str(path), codes)
    return path, codes


@pytest.mark.parametrize("command", [["convert"], ["warp", "--to", "equirect", "--filter", "nearest"]])
def test_tone_on_a_display_source_is_noted(tmp_path, capsys, png, command):
    import cv2

    path, codes = png
    out = tmp_path / "out.png"
    assert main([command[0], str(path), *command[1:], "-o", str(out), "--tone", "aces", "-q"]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if "--tone aces" in line]
    assert len(notes) == 1 and "not applied" in notes[0], err
    assert np.array_equal(cv2.imread(str(out)), codes)  # the codes as they were: no curve
    out2 = tmp_path / "out2.png"
    assert main([command[0], str(path), *command[1:], "-o", str(out2), "-q"]) == 0
    assert "--tone" not in capsys.readouterr().err


def test_a_batch_says_it_once(tmp_path, capsys, png):
    import shutil

    path, _ = png
    for i in range(3):
        shutil.copy(path, tmp_path / f"p{i}.png")
    assert main(["convert", *(str(tmp_path / f"p{i}.png") for i in range(3)), "--to", "jpg", "-o",
                 str(tmp_path / "out"), "--tone", "agx"]) == 0
    assert sum("--tone agx" in line for line in capsys.readouterr().err.splitlines()) == 1
