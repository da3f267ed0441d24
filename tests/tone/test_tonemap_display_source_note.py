"""``lenslab tonemap`` of a display image (an 8-bit PNG written by Pillow) applies the curve, as asked, and says in
one note that the image holds display values already: Hable's curve on them gives a darker picture (the value is
checked against Hable's published formula, transcribed in the tone tests), where a user expects the photo."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from tests.tone.test_tone_reference import _hable_blog  # Hable's formula, his blog post's constants

Image = pytest.importorskip("PIL.Image")
colour = pytest.importorskip("colour")


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "display values already" in line]


def test_a_png_tone_mapped_gets_the_note_and_the_curve(tmp_path, capsys):
    src = tmp_path / "photo.png"
    Image.fromarray(np.full((4, 6, 3), 200, np.uint8)).save(src)  # sRGB code 200
    out = tmp_path / "out.png"
    assert main(["tonemap", str(src), "-o", str(out), "--no-dither"]) == 0
    notes = _notes(capsys.readouterr().err)
    assert len(notes) == 1 and notes[0].startswith(f"lenslab tonemap: note: {src}: holds display values already")
    linear = colour.models.eotf_sRGB(200 / 255)
    want = round(float(colour.models.eotf_inverse_sRGB(_hable_blog(linear))) * 255)
    assert want < 190  # darker than the photo's 200
    assert np.asarray(Image.open(out))[0, 0, 0] == want


@pytest.mark.parametrize("args", [["--tone", "clamp"], []])
def test_no_note_for_clamp_or_a_scene_linear_source(tmp_path, capsys, args):
    from lenslab.io import write

    src = tmp_path / ("photo.png" if args else "scene.exr")
    if args:
        Image.fromarray(np.full((4, 6, 3), 200, np.uint8)).save(src)
    else:
        write(src, np.full((4, 6, 3), 2.0, np.float32))
    assert main(["tonemap", str(src), "-o", str(tmp_path / "out.png"), *args]) == 0
    assert _notes(capsys.readouterr().err) == []
