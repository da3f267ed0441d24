"""Usage errors name what the user typed:

- tonemap's output-format option has two spellings (``--format``, ``--to``); the message that refuses a format
  the output's name contradicts names the one given;
- an option a command does not have is reported before the arguments it is missing (argparse would report
  the missing ones and leave the misspelt option unsaid): ``python -m gallery --hel`` says ``--hel``, as
  ``lenslab --hel`` does.
"""

from __future__ import annotations

import numpy as np
import pytest

from gallery.__main__ import main as gallery
from lenslab.cli.main import main as lenslab
from lenslab.io import write
from tracer.cli import main as tracer


def usage_lines(main, argv, capsys) -> list[str]:
    """The lines on standard error of a command line that argparse refuses (exit 2)."""
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    return capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("option", ["--format", "--to"])
def test_tonemap_names_the_format_option_as_typed(tmp_path, capsys, option):
    src = tmp_path / "city.exr"
    write(src, np.full((4, 8, 3), 0.5, np.float32))
    out = tmp_path / "t.png"
    capsys.readouterr()
    assert lenslab(["tonemap", str(src), option, "jpg", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"lenslab tonemap: error: -o {out}: the name says png but the output format asked is jpg; "
                   f"give a name with the format's extension, or leave {option} out"]
    assert not out.exists()


@pytest.mark.parametrize("main, argv, prog", [
    (gallery, ["--hel"], "python -m gallery"),
    (gallery, ["out", "--hel"], "python -m gallery"),
    (lenslab, ["warp", "--hel"], "lenslab warp"),
    (lenslab, ["stmap", "--hel", "--from", "equirect"], "lenslab stmap"),
    (lenslab, ["fit", "lens", "--hel"], "lenslab fit lens"),
    (tracer, ["render", "--hel"], "tracer render"),
])
def test_an_unknown_option_is_said_before_missing_arguments(tmp_path, monkeypatch, capsys, main, argv, prog):
    monkeypatch.chdir(tmp_path)
    assert usage_lines(main, argv, capsys) == [f"{prog}: error: unrecognized arguments: --hel; --hel is not an option (options are never "
                   f"abbreviated): did you mean --help? (see '{prog} --help')"]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, missing", [
    (["warp", "--yaw", "-30"], "IN, -o/--output"),  # a negative number is the option's value, not an option
    (["warp", "--", "-o"], "-o/--output"),  # after --, a name that starts with a dash is an input
])
def test_missing_arguments_are_said_when_no_option_is_unknown(tmp_path, monkeypatch, capsys, argv, missing):
    monkeypatch.chdir(tmp_path)
    assert usage_lines(lenslab, argv, capsys) == [f"lenslab warp: error: the following arguments are required: {missing} "
                   "(see 'lenslab warp --help')"]
