"""The parsers of the command lines, walked from the programs' own parser trees (never from a hand-kept list),
for the tests of options that every command shares."""

from __future__ import annotations

import argparse


def parsers(parser: argparse.ArgumentParser):
    """``parser`` and every subparser under it, depth first."""
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from parsers(sub)


def loosened(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """``parser`` with its required arguments made optional, so that the options under test are parsed alone."""
    for action in parser._actions:
        action.required = False
    for group in parser._mutually_exclusive_groups:
        group.required = False
    return parser
