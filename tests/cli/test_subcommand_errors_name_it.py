"""An error of a command with subcommands names the subcommand that failed (``lenslab fit lens: error: ...``),
as argparse's own usage errors of that subcommand do: the funnel's line and the parser's agree, so a user knows
which ``--help`` to read. Every command group is covered: the cases are checked against the parser's groups."""

from __future__ import annotations

import argparse

import pytest

from lenslab.cli.main import build_parser, main


def _groups() -> set[tuple[str, str]]:
    """(command, subcommand) of every lenslab command that has subcommands, read from the parser."""
    found = set()
    top = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, parser in top.choices.items():
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                found |= {(name, sub) for sub in action.choices}
    return found


def _bench_targets() -> list[str]:
    return sorted(sub for name, sub in _groups() if name == "bench")


#: a failing run of each subcommand that reaches the funnel (not argparse), and the message after the prefix
CASES = {
    ("fit", "lens"): (["--from", "fisheye:fov=360", "--model", "perspective", "--size", "32x32"], "no good fit"),
    ("fit", "points"): (["{tmp}/none.csv", "--model", "fisheye", "--size", "32x32"], "{tmp}/none.csv: "),
    ("fit", "tone"): (["{tmp}/none.exr", "{tmp}/none.png"], "{tmp}/none.exr: "),
    ("camera", "show"): (["{tmp}/none.yaml"], "{tmp}/none.yaml: "),
    ("camera", "convert"): (["{tmp}/none.yaml", "-o", "{tmp}/out.yaml"], "{tmp}/none.yaml: "),
    **{("bench", t): (["--json", "{tmp}/there.json"], "{tmp}/there.json: already exists") for t in _bench_targets()},
}


def test_every_command_group_is_covered():
    assert set(CASES) == _groups()


@pytest.mark.parametrize("group, sub", sorted(CASES))
def test_an_error_names_the_subcommand(tmp_path, capsys, group, sub):
    (tmp_path / "there.json").write_text("{}")
    extra, words = CASES[group, sub]
    argv = [group, sub, *(a.replace("{tmp}", str(tmp_path)) for a in extra)]
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert code in (1, 2) and len(err) == 1, err
    assert err[0].startswith(f"lenslab {group} {sub}: error: {words.replace('{tmp}', str(tmp_path))}"), err


@pytest.mark.parametrize("group, sub", [("fit", "tone"), ("camera", "convert")])
def test_the_parser_and_the_funnel_name_the_same_command(tmp_path, capsys, group, sub):
    with pytest.raises(SystemExit) as exc:  # argparse's usage error: a required argument missing
        main([group, sub])
    assert exc.value.code == 2
    assert capsys.readouterr().err.startswith(f"lenslab {group} {sub}: error: the following arguments are required")
