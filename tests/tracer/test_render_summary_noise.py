"""``tracer render``'s summary line says the noise of the image it made: a percentage with what it measures,
or, at one sample per pixel, that it is unknown and why, without a second parenthesis explaining a figure
that is not there."""

from __future__ import annotations

from tracer.cli import main as tracer


def test_one_sample_says_the_noise_is_unknown_once(tmp_path, capsys):
    out = tmp_path / "r.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", "fisheye:fov=180", "--size", "16x16", "--spp", "1",
                   "-o", str(out)]) == 0
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.endswith("noise unknown (fewer than 2 samples per pixel)"), line


def test_two_samples_say_what_the_percentage_measures(tmp_path, capsys):
    out = tmp_path / "r.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", "fisheye:fov=180", "--size", "16x16", "--spp", "4",
                   "-o", str(out)]) == 0
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert "% (RMS standard error of the pixel means, relative to the image's mean value)" in line, line
