"""``--exposure auto`` in convert and warp says the stops it found for each image, as tonemap does, so that a batch
can be repeated with a fixed ``--exposure``. A grey of 0.72 goes to middle grey 0.18: log2(0.18 / 0.72) = -2 stops,
and the pixel written is Hable's curve (his published formula, transcribed in the tone tests) of 0.18."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write
from tests.tone.test_tone_reference import _hable_blog  # Hable's formula, his blog post's constants

colour = pytest.importorskip("colour")
Image = pytest.importorskip("PIL.Image")


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "auto exposure" in line]


def test_convert_says_the_stops_and_uses_them(tmp_path, capsys):
    src = tmp_path / "grey.exr"
    write(src, np.full((8, 16, 3), 0.72, np.float32), pixel_type="float")
    out = tmp_path / "grey.png"
    assert main(["convert", str(src), "-o", str(out), "--exposure", "auto"]) == 0
    stops = math.log2(0.18 / 0.72)
    assert _notes(capsys.readouterr().err) == [f"lenslab convert: note: {src}: auto exposure {stops:+.2f} stops"]
    want = round(float(colour.models.eotf_inverse_sRGB(_hable_blog(0.18))) * 255)
    assert abs(int(np.asarray(Image.open(out))[4, 8, 0]) - want) <= 1  # (dithered by one code at most)


def test_warp_says_them_too_and_a_clip_of_images_does_not_repeat_them(tmp_path, capsys):
    src = tmp_path / "grey.exr"
    write(src, np.full((8, 16, 3), 0.72, np.float32), pixel_type="float")
    assert main(["warp", str(src), "-o", str(tmp_path / "w.png"), "--to", "equirect", "--exposure", "auto"]) == 0
    stops = math.log2(0.18 / 0.72)
    assert _notes(capsys.readouterr().err) == [f"lenslab warp: note: {src}: auto exposure {stops:+.2f} stops"]
    pytest.importorskip("av")
    frames = [str(src)] * 3
    assert main(["convert", *frames, "-o", str(tmp_path / "clip.mkv"), "--exposure", "auto"]) == 0
    assert _notes(capsys.readouterr().err) == []  # a line per frame would bury the command's other notes
