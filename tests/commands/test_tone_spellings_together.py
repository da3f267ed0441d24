"""Two spellings of the tone-curve option given together (``--tone aces --curve hable``, ``--curves a,b --tone c``)
used to keep the last silently: two that name different curves are a usage error (exit 2, one line naming both);
the same curve under two spellings is taken. The options are found in the parser trees of ``lenslab`` and
``tracer``, so a command added later is covered."""

from __future__ import annotations

import contextlib
import io
import itertools

import numpy as np
import pytest

from lenslab.cli.main import build_parser, main
from lenslab.io import write
from tracer.cli import build_parser as tracer_parser
from tests.commands.parser_tree import loosened, parsers

TONE_SPELLINGS = {"--tone", "--curve", "--curves", "--tones"}


def _tone_actions():
    rows = []
    for make in (build_parser, tracer_parser):
        for parser in parsers(make()):
            for action in parser._actions:
                spellings = [o for o in action.option_strings if o in TONE_SPELLINGS]
                if len(spellings) > 1:
                    rows.append((parser.prog, parser, spellings))
    return rows


ROWS = _tone_actions()


def _parse(parser, argv):
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            return 0, parser.parse_args(argv), err.getvalue()
    except SystemExit as stop:
        return int(stop.code), None, err.getvalue()


def test_every_command_with_a_curve_option_is_found():
    assert {prog for prog, _, _ in ROWS} == {
        "lenslab warp", "lenslab convert", "lenslab tonemap", "lenslab fit tone", "tracer render",
        "lenslab curves", "lenslab compare-tones", "lenslab bench tone"}


@pytest.mark.parametrize("prog,parser,spellings", ROWS, ids=[r[0] for r in ROWS])
def test_two_spellings_naming_different_curves_are_refused(prog, parser, spellings):
    parser = loosened(parser)
    for first, second in itertools.permutations(spellings, 2):
        code, _, err = _parse(parser, [first, "hable", second, "aces"])
        assert code == 2, (first, second)
        assert err.count("\n") == 1 and f"{first} hable" in err and f"{second} aces" in err, err


@pytest.mark.parametrize("prog,parser,spellings", ROWS, ids=[r[0] for r in ROWS])
def test_the_same_curve_under_two_spellings_is_taken(prog, parser, spellings):
    """Curve names compare as the tone registry compares them: in any case, ``_`` for ``-``."""
    parser = loosened(parser)
    dest = parser._option_string_actions[spellings[0]].dest
    for first, second in itertools.permutations(spellings, 2):
        code, args, err = _parse(parser, [first, "pbr_neutral", second, "PBR-Neutral"])
        assert code == 0, err
        assert getattr(args, dest) == "PBR-Neutral"


def test_lists_that_differ_are_refused_and_equal_lists_taken():
    parser = loosened(next(p for prog, p, _ in ROWS if prog == "lenslab compare-tones"))
    assert _parse(parser, ["--curves", "hable,aces", "--tone", "aces"])[0] == 2
    code, args, _ = _parse(parser, ["--curves", "hable,aces", "--curve", "Hable, ACES"])
    assert code == 0 and args.curves == "Hable, ACES"


def test_tonemap_writes_nothing_when_two_curves_are_named(tmp_path):
    src = tmp_path / "pano.exr"
    write(src, np.full((4, 8, 3), 0.5, np.float32))
    out = tmp_path / "out.png"
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as stop:
        main(["tonemap", str(src), "-o", str(out), "--tone", "aces", "--curve", "hable"])
    assert stop.value.code == 2
    assert err.getvalue() == ("lenslab tonemap: error: --tone aces and --curve hable name different curves; give one "
                              "(see 'lenslab tonemap --help')\n")
    assert not out.exists()
