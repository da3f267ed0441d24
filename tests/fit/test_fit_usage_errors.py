"""``lenslab fit`` and ``lenslab camera convert --model``: a model, parameter, ``--free`` name or ``--bounds``
that names nothing is a mistake in what was typed, so a usage error (exit status 2, as for ``warp --to`` and
``tracer render --camera``), said in one line before any fit runs; a fit that runs and falls short stays a
failure (exit status 1)."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main

SOURCE = ["--from", "fisheye:fov=180", "--size", "32x32"]


@pytest.mark.parametrize("extra, words", [
    (["--model", "no-such-lens"], "unknown lens model 'no-such-lens'"),
    (["--model", "fisheye:zoom=2"], "unknown parameter(s) zoom"),
    (["--model", "fisheye", "--free", "zoom"], "cannot fit 'zoom'"),
    (["--model", "fisheye", "--bounds", "fov=200:100"], "bounds for fov are empty"),
    (["--model", "fisheye", "--bounds", "fov"], "expected NAME=LOW:HIGH"),
])
def test_fit_lens_names_nothing_usage_error(capsys, extra, words):
    assert main(["fit", "lens", *SOURCE, *extra]) == 2
    out, err = capsys.readouterr()
    assert out == ""  # no fit ran, no report
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lenslab fit lens: error: ") and words in lines[0], lines


def test_camera_convert_to_an_unknown_model_is_a_usage_error(tmp_path, capsys):
    out = tmp_path / "cam.yaml"
    spec = "opencv:fx=90,fy=90,cx=31.5,cy=23.5,k1=-0.2,width=64,height=48"
    assert main(["camera", "convert", spec, "-o", str(out), "--model", "no-such-lens"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert not out.exists()


def test_a_fit_that_falls_short_is_still_a_failure(capsys):
    # a swirl is no fisheye: the fit runs, reports and misses the 0.5 px aim
    assert main(["fit", "lens", "--from", "swirl:amount=6", "--size", "32x32", "--model", "fisheye"]) == 1
    out, err = capsys.readouterr()
    assert "verdict" in out and "no good fit" in err
