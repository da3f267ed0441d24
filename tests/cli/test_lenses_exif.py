"""``lenslab lenses exif``: exif is no model of its own, but the spec a photo's own lens is read by; the listing says
what it is (exit 0) instead of calling it an unknown model (exit 2). The half diagonal it quotes is the 36 x 24 mm
frame's, hypot(36, 24) / 2, to the 0.01 mm it prints."""

from __future__ import annotations

import math
import re

from lenslab.cli.main import main


def test_lenses_exif_says_what_it_is(capsys):
    assert main(["lenses", "exif"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("exif: A photo's own lens: --from exif") and "lensfun:auto" in out
    half = float(re.search(r"tan\(FOV/2\) = ([0-9.]+) mm / f35", out).group(1))
    assert abs(half - math.hypot(36.0, 24.0) / 2) < 0.005


def test_lenses_lensfun_auto_says_what_it_is(capsys):
    assert main(["lenses", "lensfun:auto"]) == 0
    assert capsys.readouterr().out.startswith("lensfun:auto: A photo's own lens: --from exif")


def test_an_unknown_model_is_still_refused(capsys):
    assert main(["lenses", "exiff"]) == 2
    assert "unknown lens model 'exiff'" in capsys.readouterr().err
