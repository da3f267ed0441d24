"""One tone-curve option, whatever the command: ``--tone CURVE`` on every command that takes one curve, with
``--curve`` accepted for it; ``--curves`` on the commands that take several, with ``--tone`` and ``--curve``
accepted. A script written for one command works for every other, and ``--help`` shows ``--tone`` first."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import build_parser, main
from lenslab.io import read, write
from tracer.cli import build_parser as tracer_parser
from tests.commands.parser_tree import parsers

ONE = ("--tone", "--curve")
SEVERAL = ("--curves", "--tone", "--curve")
#: every command that names a tone curve, and the spellings it takes (first: the one --help shows)
EXPECTED = {
    "lenslab warp": ONE, "lenslab convert": ONE, "lenslab tonemap": ONE, "lenslab fit tone": ONE,
    "tracer render": ONE,
    "lenslab curves": SEVERAL, "lenslab compare-tones": SEVERAL, "lenslab bench tone": SEVERAL,
}


def _tone_options() -> dict[str, tuple[str, ...]]:
    found = {}
    for parser in [*parsers(build_parser()), *parsers(tracer_parser())]:
        for action in parser._actions:
            if {"--tone", "--tones", "--curve", "--curves"} & set(action.option_strings):
                found[parser.prog] = tuple(action.option_strings)
    return found


def test_every_command_takes_every_spelling_with_tone_first():
    assert _tone_options() == EXPECTED


@pytest.mark.parametrize("prog", sorted(EXPECTED))
def test_help_shows_the_chosen_spelling_first(prog, capsys):
    words = prog.split()
    run = main if words[0] == "lenslab" else (lambda argv: tracer_parser().parse_args(argv))
    with pytest.raises(SystemExit) as exc:
        run([*words[1:], "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    metavar = "CURVE" if EXPECTED[prog] == ONE else "CURVES"
    assert ", ".join(f"{o} {metavar}" for o in EXPECTED[prog]) in text


@pytest.fixture
def pano(tmp_path):
    p = tmp_path / "pano.exr"
    rng = np.random.default_rng(3)
    write(p, np.exp(rng.normal(0, 2, (16, 32, 3))).astype(np.float32))
    return p


@pytest.mark.parametrize("command", [["tonemap", "--no-dither"], ["convert", "--to", "png"],
                                     ["warp", "--to", "fisheye:fov=180", "--size", "16x16"]])
def test_each_spelling_gives_the_same_image(tmp_path, pano, command):
    """``--curve aces`` and ``--tone aces`` give the same file, and it is not the default curve's (hable)."""
    images = {}
    for option in ("--tone", "--curve", None):
        out = tmp_path / f"{option or 'default'}.png"
        assert main([command[0], str(pano), *command[1:], "-o", str(out), "-q",
                     *([option, "aces"] if option else [])]) == 0
        images[option] = read(out)[0]
    np.testing.assert_array_equal(images["--tone"], images["--curve"])
    assert not np.array_equal(images["--tone"], images[None])


def test_a_list_command_takes_one_curve_by_the_single_spelling(tmp_path, pano, capsys):
    """``compare-tones --tone aces`` is the strip of that one curve, as ``--curves aces`` is."""
    for option in ("--curves", "--tone", "--curve"):
        out = tmp_path / f"{option[2:]}.png"
        assert main(["compare-tones", str(pano), "-o", str(out), option, "aces", "--panel-width", "32", "-q"]) == 0
        assert read(out)[0].shape[1] == 32  # one panel
