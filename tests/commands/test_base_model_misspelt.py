"""A misspelt base model inside a spec (``stereo:base=fishey``, ``swirl:base=fishey``) is an unknown lens model,
with the nearest model, whether or not ``--size`` is given: a base names a model, never a file, so the line does
not say that no file of that name exists (as it does of a bare ``--to fishey``, which could have named one).

Outside value: the model names lenslab's registry lists are the ones ``lenslab lenses`` prints; the nearest is
``fisheye``, one letter away (difflib's ratio 0.92, over the 0.75 the hints take)."""

from __future__ import annotations

from difflib import SequenceMatcher

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.mark.parametrize("size", [[], ["--size", "64x32"]])
@pytest.mark.parametrize("spec", ["stereo:base=fishey", "swirl:base=fishey", "stereo:base=fishey,layout=tb"])
def test_a_misspelt_base_is_an_unknown_model(tmp_path, capsys, spec, size):
    assert SequenceMatcher(None, "fishey", "fisheye").ratio() > 0.75
    write(tmp_path / "pano.exr", np.ones((16, 32, 3), np.float32))
    assert main(["warp", str(tmp_path / "pano.exr"), "-o", str(tmp_path / "out.exr"), "--to", spec, *size]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "unknown lens model 'fishey' (did you mean fisheye?)" in lines[0], lines
    assert "no file" not in lines[0]


def test_tracer_render_says_the_same(tmp_path, capsys):
    from tracer.cli import main as tracer_main

    assert tracer_main(["render", "--scene", "cornell", "--camera", "stereo:base=fishey", "--spp", "1",
                        "-o", str(tmp_path / "t.exr")]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "unknown lens model 'fishey' (did you mean fisheye?)" in lines[0], lines
