"""Usage mistakes that do not depend on a file are found once, before any work: exit 2, one line, no folder.

The table of options comes from the parsers themselves (every option of every command whose value is
checked by a type), so an option added later is checked too. The values are the hostile ones users
type: NaN and infinities are never a valid number of anything.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import build_parser, main
from lenslab.io import write
from lenslab.jobs.arguments import non_empty


def lenslab(argv: list[str]) -> int:
    """The command's exit code, whether it returns it or argparse ends it (SystemExit)."""
    try:
        return main(argv)
    except SystemExit as stop:
        return int(stop.code)


def _subparsers(parser) -> dict[str, argparse.ArgumentParser]:
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def _typed_options():
    """(program, command, option, type) for every option with a type function, lenslab's and the tracer's."""
    from tracer.cli import build_parser as tracer_parser

    rows = []
    for prog, parser in (("lenslab", build_parser()), ("tracer", tracer_parser())):
        for name, sub in _subparsers(parser).items():
            for action in sub._actions:
                if action.option_strings and callable(action.type) and action.type not in (str, Path, non_empty):
                    rows.append((prog, name, action.option_strings[-1], action.type))
    return rows


TYPED = _typed_options()


def test_the_table_covers_the_options_of_the_batch_commands():
    names = {(c, o) for _, c, o, _ in TYPED}
    assert {("warp", "--yaw"), ("warp", "--look-at"), ("warp", "--samples"), ("convert", "--rate"),
            ("stmap", "--yaw"), ("curves", "--exposure"), ("validate", "--yaw"), ("render", "--yaw"),
            ("warp", "--scheduler-timeout")} <= names


@pytest.mark.parametrize("prog,command,option,kind", TYPED, ids=[f"{p} {c} {o}" for p, c, o, _ in TYPED])
@pytest.mark.parametrize("value", ["nan", "NaN", "inf", "-inf", "1e400"])
def test_no_option_takes_a_non_finite_number(prog, command, option, kind, value):
    text = value if kind.__name__ not in ("finite_vector", "_vec3", "_triple") else f"{value},0,1"
    with pytest.raises((argparse.ArgumentTypeError, ValueError, TypeError)):
        kind(text)


@pytest.fixture()
def folder(tmp_path) -> Path:
    (tmp_path / "in").mkdir()
    for i in range(2):
        write(tmp_path / "in" / f"p{i}.exr", np.full((8, 16, 3), 0.5, np.float32))
    return tmp_path


#: the mistakes users made, with the command that reports them (run on a folder of two panoramas)
MISTAKES = [
    ("warp", ["--to", "fisheye", "--yaw", "nan"]),
    ("warp", ["--to", "fisheye", "--pitch", "inf"]),
    ("warp", ["--to", "fisheye", "--look-at", "nan,0,1"]),
    ("warp", ["--to", "fisheye", "--look-at", "0,0,0"]),
    ("warp", ["--to", "fisheye", "--eye", "0,nan,0"]),
    ("warp", ["--to", "fisheye", "--samples", "100000"]),
    ("warp", ["--to", "fisheye", "--samples", "0"]),
    ("warp", ["--to", "fisheye", "--exposure", "nan"]),
    ("warp", ["--to", "fisheye", "--scheduler-timeout", "0"]),
    ("convert", ["--to", "jpg", "--exposure", "inf"]),
    ("convert", ["--to", "mp4", "--rate", "0"]),
    ("convert", ["--to", "mp4", "--rate", "-24"]),
    ("convert", ["--to", "mp4", "--rate", "1e308"]),
    ("convert", ["--to", "mp4", "--rate", "nan"]),
    ("convert", ["--to", "exr", "--compression", "gzip9"]),
    ("convert", ["--to", "jpg", "--bits", "16"]),
    ("tonemap", ["--exposure", "nan"]),
]


@pytest.mark.parametrize("command,args", MISTAKES, ids=[" ".join(a) for _, a in MISTAKES])
def test_a_usage_mistake_is_one_line_exit_2_and_no_folder(folder, command, args, capsys):
    out = folder / "out"
    status = lenslab([command, str(folder / "in"), "-o", str(out), *args])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert not out.exists()


#: an output name that says another format than the format option
CLASHES = [
    ("convert", "b.exr", ["--to", "jpg"]),
    ("convert", "b.png", ["--to", "exr"]),
    ("convert", "b.tif", ["--to", "pfm"]),
    ("warp", "b.jpg", ["--to", "fisheye", "--format", "exr"]),
    ("warp", "b.exr", ["--to", "fisheye", "--format", "png"]),
]


@pytest.mark.parametrize("command,name,args", CLASHES, ids=[f"{c} -o {n} {' '.join(a)}" for c, n, a in CLASHES])
def test_an_output_name_of_another_format_than_asked_is_a_usage_error(folder, command, name, args, capsys):
    out = folder / name
    status = lenslab([command, str(folder / "in" / "p0.exr"), "-o", str(out), *args])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.count("\n") == 1 and name in err, err
    assert not out.exists()


def test_the_same_format_by_another_extension_is_fine(folder, capsys):
    out = folder / "b.jpeg"
    assert lenslab(["convert", str(folder / "in" / "p0.exr"), "--to", "jpg", "-o", str(out), "-q"]) == 0
    assert out.read_bytes()[:3] == b"\xff\xd8\xff"  # JPEG's start-of-image marker
