"""A misspelt option that begins no option (``--src-size`` for ``--source-size``, ``--szie`` for ``--size``) is still a
usage error (exit 2) that names the option meant, as an abbreviation's does; a word like no option gets no guess.
The options expected are the commands' own, as their --help lists them."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main


@pytest.mark.parametrize("argv, meant", [
    (["stmap", "-o", "st.exr", "--from", "equirect", "--to", "fisheye", "--size", "8x8", "--src-size", "16x8"],
     "--source-size"),
    (["warp", "in.exr", "-o", "out.exr", "--to", "fisheye", "--szie", "8x8"], "--size"),
    (["convert", "in.exr", "-o", "out.png", "--overwirte"], "--overwrite"),
])
def test_the_option_meant_is_named(capsys, argv, meant):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(f"did you mean {meant}? (see 'lenslab {argv[0]} --help')"), err


def test_no_guess_for_a_word_like_no_option(capsys):
    with pytest.raises(SystemExit):
        main(["warp", "in.exr", "-o", "out.exr", "--to", "fisheye", "--zzzzqqq"])
    assert "did you mean" not in capsys.readouterr().err
