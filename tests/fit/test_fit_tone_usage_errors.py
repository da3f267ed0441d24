"""``lenslab fit tone``: a curve, ``--param``, ``--free`` or ``--bounds`` that names nothing is a mistake in
what was typed, a usage error (exit status 2) said in one line before either image is read, as for
``fit lens`` and ``tonemap --tone``; a missing image stays a failed input (exit status 1)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

MISSING = ["no-such-render.exr", "no-such-photo.png"]  # never opened when the names are wrong


@pytest.mark.parametrize("extra, words", [
    (["--tone", "no-such-curve"], "unknown tone curve 'no-such-curve'"),
    (["--curve", "hable", "--free", "zoom"], "no numeric parameter 'zoom'"),
    (["--param", "zoom=2"], "no parameter 'zoom'"),
    (["--param", "white"], "expected NAME=VALUE"),
    (["--bounds", "white"], "expected NAME=LOW:HIGH"),
    (["--free", "exposure", "--bounds", "white=1:9"], "bounds given for white, which is not fitted"),
])
def test_fit_tone_names_nothing_usage_error(capsys, extra, words):
    assert main(["fit", "tone", *MISSING, *extra]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lenslab fit tone: error: ") and words in lines[0], lines


def test_fit_tone_missing_image_is_a_failed_input(capsys):
    assert main(["fit", "tone", *MISSING, "--tone", "hable"]) == 1
    assert "no-such-render.exr" in capsys.readouterr().err


def test_fit_tone_still_fits(tmp_path, capsys):
    # Reinhard one stop up, y = 2x / (1 + 2x), written in float64 here: the fit gives the stop back
    import lenslab

    x = np.random.default_rng(3).uniform(0.0, 4.0, (16, 16, 3))
    hdr, ldr = tmp_path / "r.exr", tmp_path / "s.pfm"
    lenslab.write(hdr, x.astype(np.float32))
    lenslab.write(ldr, (2 * x / (1 + 2 * x)).astype(np.float32))
    assert main(["fit", "tone", str(hdr), str(ldr), "--tone", "reinhard"]) == 0
    assert "exposure=1" in capsys.readouterr().out
