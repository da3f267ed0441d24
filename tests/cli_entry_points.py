"""Every command of every entry point, found from the parsers themselves, and a way to run one in-process.

The entry points: ``lenslab`` (its COMMANDS and the ``lenslab.commands`` entry-point group, nested
actions such as ``fit lens`` included), ``tracer`` (its subcommands) and ``python -m gallery``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Command:
    name: str  # as a user types it: "lenslab warp", "lenslab fit lens", "tracer render", "python -m gallery"
    prefix: tuple[str, ...]  # argv before the command's own arguments
    main: Callable[[list[str]], int]
    parser: argparse.ArgumentParser  # the command's own parser


def _subparsers(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return None


def _leaves(prog: str, prefix: tuple[str, ...], main, parser) -> list[Command]:
    subs = _subparsers(parser)
    if not subs:
        return [Command(" ".join((prog,) + prefix), prefix, main, parser)]
    out = []
    for name, sub in subs.items():
        out += _leaves(prog, prefix + (name,), main, sub)
    return out


def all_commands() -> list[Command]:
    from gallery.__main__ import build_parser as gallery_parser
    from gallery.__main__ import main as gallery_main
    from lenslab.cli.main import build_parser as lenslab_parser
    from lenslab.cli.main import main as lenslab_main
    from tracer.cli import build_parser as tracer_parser
    from tracer.cli import main as tracer_main

    return (_leaves("lenslab", (), lenslab_main, lenslab_parser())
            + _leaves("tracer", (), tracer_main, tracer_parser())
            + [Command("python -m gallery", (), gallery_main, gallery_parser())])


def run(command: Command, args: list[str]) -> tuple[int, str, str]:
    """Run in this process; returns (exit code, stdout, stderr). argparse's SystemExit is an exit code."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = command.main([*command.prefix, *args])
        except SystemExit as exc:  # as the interpreter does: a text is printed and means exit status 1
            if isinstance(exc.code, str):
                print(exc.code, file=err)
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    return int(code), out.getvalue(), err.getvalue()
