"""Two spellings of the output-format option given together (``--to jpg --format png`` in ``convert`` and
``tonemap``, where ``--to`` is ``--format``) used to keep the last silently, as the tone-curve spellings did:
two that name different formats are a usage error (exit 2, the brief's code for usage, one line naming both);
the same format under both spellings is taken. The options are found in the parser trees of ``lenslab``."""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from lenslab.cli.main import build_parser, main
from lenslab.io import write
from tests.commands.parser_tree import loosened, parsers
from tests.commands.test_tone_spellings_together import _parse

ROWS = [(parser.prog, parser, action.dest) for parser in parsers(build_parser()) for action in parser._actions
        if {"--to", "--format"} <= set(action.option_strings)]


def test_the_commands_with_both_spellings_are_found():
    assert {prog for prog, _, _ in ROWS} == {"lenslab convert", "lenslab tonemap"}


@pytest.mark.parametrize("prog,parser,dest", ROWS, ids=[r[0] for r in ROWS])
def test_two_spellings_naming_different_formats_are_refused(prog, parser, dest):
    parser = loosened(parser)
    for first, second in (("--to", "--format"), ("--format", "--to")):
        code, _, err = _parse(parser, [first, "jpg", second, "png"])
        assert code == 2, (first, second)
        assert err.count("\n") == 1 and f"{first} jpg" in err and f"{second} png" in err, err


@pytest.mark.parametrize("prog,parser,dest", ROWS, ids=[r[0] for r in ROWS])
def test_the_same_format_under_both_spellings_is_taken(prog, parser, dest):
    parser = loosened(parser)
    code, args, err = _parse(parser, ["--to", "png", "--format", "png"])
    assert code == 0 and getattr(args, dest) == "png", err


@pytest.mark.parametrize("command", ["convert", "tonemap"])
def test_nothing_is_written_when_two_formats_are_named(tmp_path, command):
    src = tmp_path / "pano.exr"
    write(src, np.full((4, 8, 3), 0.5, np.float32))
    out = tmp_path / "out"
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as stop:
        main([command, str(src), "-o", str(out), "--to", "jpg", "--format", "png"])
    assert stop.value.code == 2
    assert err.getvalue() == (f"lenslab {command}: error: --to jpg and --format png name different formats; give one "
                              f"(see 'lenslab {command} --help')\n")
    assert not out.exists()
