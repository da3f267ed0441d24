"""``--autoscale`` takes an optional MODE, so given before the input files it takes the first file as its mode:
the usage error (exit 2) says to put it after the input files, as its --help does; a mistyped mode is still named
with the two modes there are (argparse's own words for a choice)."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main


def _error(argv, capsys) -> str:
    capsys.readouterr()
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    return capsys.readouterr().err.strip()


def test_before_the_inputs(tmp_path, capsys):
    err = _error(["warp", "--autoscale", "pano.exr", "-o", "out.exr", "--to", "fisheye"], capsys)
    assert "invalid choice: 'pano.exr' (choose from 'fill', 'cover')" in err
    assert "put --autoscale after the input files" in err


def test_a_mistyped_mode(capsys):
    err = _error(["warp", "pano.exr", "-o", "out.exr", "--to", "fisheye", "--autoscale", "fit"], capsys)
    assert "invalid choice: 'fit' (choose from 'fill', 'cover')" in err
    assert "after the input files" not in err
