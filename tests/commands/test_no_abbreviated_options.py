"""No option a user types is read as another: argparse's prefix matching is off on every parser and
subparser of ``lenslab``, ``tracer``, ``python -m gallery`` and the scripts under ``tools/`` (``--to`` is not
``--tone``, ``--only`` is not ``--only-threads``, ``--read`` is not ``--readme``), an unknown prefix is a usage error
that names the option meant, and every command line the README, the docs pages and the commands' own ``--help``
show still parses as written.

The parsers are walked from the programs' own parser trees, and the tools from the files under ``tools/`` that
make a parser, so a command or a tool added later is covered too.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

from gallery.__main__ import build_parser as gallery_parser
from lenslab.cli.main import build_parser, main
from lenslab.io import write
from tracer.cli import build_parser as tracer_parser
from tests.commands.parser_tree import loosened, parsers

REPO = Path(__file__).resolve().parents[2]
PROGRAMS = {"lenslab": build_parser, "tracer": tracer_parser, "python -m gallery": gallery_parser}


def _tools() -> dict:
    """``python tools/NAME.py``: the ``build_parser`` of every script under tools/ that makes an argparse parser."""
    import importlib.util

    found = {}
    for path in sorted((REPO / "tools").rglob("*.py")):
        if "ArgumentParser" in path.read_text(encoding="utf-8"):
            spec = importlib.util.spec_from_file_location(f"_tool_{path.stem}", path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            found[f"python {path.relative_to(REPO).as_posix()}"] = module.build_parser
    return found


TOOLS = _tools()
PROGRAMS.update(TOOLS)


ALL = [p for make in PROGRAMS.values() for p in parsers(make())]


def _exit(parse, argv) -> tuple[int, str]:
    """The exit code of ``parse(argv)`` (a parser's: 0 when it parses; ``main``'s: the code it returns) and what
    it printed on stderr."""
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            result = parse(argv)
    except SystemExit as stop:
        return int(stop.code or 0), err.getvalue()
    return (result if isinstance(result, int) else 0), err.getvalue()


def test_the_walk_finds_every_command():
    progs = {p.prog for p in ALL}
    assert {"lenslab tonemap", "lenslab bench warp", "lenslab fit tone", "lenslab camera convert", "lenslab demo",
            "lenslab validate", "tracer render", "tracer bench", "python -m gallery"} <= progs
    assert {"python tools/speed_table.py", "python tools/budget_ratios.py", "python tools/docs_tables.py"} <= progs


@pytest.mark.parametrize("argv,left,meant", [
    (["tools/speed_table.py", "--read", "t.md", "r.json"], "--read", "--readme"),
    (["tools/docs_tables.py", "--chec"], "--chec", "--check"),
    (["tools/budget_ratios.py", "--view", "1"], "--view 1", "--views"),
])
def test_a_tool_run_with_a_prefix_is_a_usage_error(argv, left, meant):
    """The script as a user runs it: exit 2 and one line naming the option meant (plain argparse took the prefix
    for the option, and budget_ratios.py would have started its five-minute run)."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, *argv], cwd=REPO, capture_output=True, text=True)
    prog, prefix = f"python {argv[0]}", argv[1]
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr == (f"{prog}: error: unrecognized arguments: {left}; {prefix} is not an option (options are "
                           f"never abbreviated): did you mean {meant}? (see '{prog} --help')\n")


@pytest.mark.parametrize("parser", ALL, ids=[p.prog for p in ALL])
def test_no_parser_matches_prefixes(parser):
    assert parser.allow_abbrev is False


@pytest.mark.parametrize("prog", sorted({p.prog for p in ALL}))
def test_a_prefix_of_an_option_is_not_that_option(prog):
    """Each long option cut by its last letter (when that is no option of the parser itself) is left over by
    argparse's own ``parse_known_args`` instead of being read as the option, and the error names the option
    meant. (The parser's required arguments are made optional here, so that the word alone is parsed.)"""
    parser = loosened(next(p for make in PROGRAMS.values() for p in parsers(make()) if p.prog == prog))
    options = parser._option_string_actions
    cut = sorted({o[:-1] for o in options if o.startswith("--") and len(o) > 4 and o[:-1] not in options})
    for word in cut:
        namespace, left = parser.parse_known_args([word])
        assert left == [word], word
        meant = sorted(o for o in options if o.startswith(word))
        assert f"did you mean {' or '.join(meant)}?" in parser.options_meant(left), word


def test_bench_warp_only_is_refused_not_read_as_only_threads():
    code, err = _exit(build_parser().parse_args, ["bench", "warp", "--only"])
    assert code == 2
    assert err.count("\n") == 1 and "--only-threads" in err


def test_curves_to_names_tone(tmp_path):
    """A command without an output-format option: ``--to`` is a usage error naming ``--tone``."""
    code, err = _exit(main, ["curves", "--to", "aces", "-o", str(tmp_path / "x.png")])
    assert code == 2
    assert err.startswith("lenslab curves: error: unrecognized arguments: --to aces")
    assert "did you mean --tone?" in err


@pytest.fixture
def pano(tmp_path) -> Path:
    path = tmp_path / "pano.exr"
    write(path, np.exp(np.random.default_rng(5).normal(0, 1, (8, 16, 3))).astype(np.float32))
    return path


def test_tonemap_to_is_the_output_format_as_in_convert(tmp_path, pano):
    """``tonemap --to jpg`` writes JPEG into the folder (JPEG's SOI marker, FF D8 FF, from the JPEG standard),
    as ``convert --to jpg`` does; it used to be read as ``--tone jpg``."""
    for command in ("tonemap", "convert"):
        out = tmp_path / command
        assert main([command, str(pano), "--to", "jpg", "-o", str(out), "-q"]) == 0
        written = sorted(out.iterdir())
        assert [p.name for p in written] == ["pano.jpg"]
        assert written[0].read_bytes()[:3] == b"\xff\xd8\xff"


def test_tonemap_to_that_differs_from_the_name_is_refused(tmp_path, pano):
    code, err = _exit(main, ["tonemap", str(pano), "--to", "jpg", "-o", str(tmp_path / "a.png")])
    assert code == 2 and "leave --to out" in err  # the option as typed
    assert not (tmp_path / "a.png").exists()


# -- the command lines the docs show ------------------------------------------------------------------------

def _fenced(text: str) -> list[str]:
    """The lines of the fenced code blocks of a Markdown page, continuation lines joined."""
    lines, inside, joined = [], False, ""
    for line in text.splitlines():
        if line.strip().startswith("```"):
            inside = not inside
            continue
        if inside:
            joined = f"{joined} {line.strip()}" if joined else line.strip()
            if joined.endswith("\\"):
                joined = joined[:-1]
                continue
            lines.append(joined)
            joined = ""
    return lines


def _commands(lines) -> list[str]:
    """The program invocations in shell lines: prompts, comments, redirections and pipes left out."""
    found = []
    for line in lines:
        line = re.sub(r"^\$\s+", "", line.strip())
        line = re.sub(r"\s+#.*$", "", line)  # a comment (a '#' inside a word, as cameras.txt#1, is not one)
        for part in re.split(r"\s*(?:&&|\|\||;|\|)\s*", line):
            part = re.sub(r"\s+>.*$", "", part)
            for prog in PROGRAMS:
                if part.startswith(prog + " ") and not part.startswith(prog + ":") and \
                        not re.match(rf"{re.escape(prog)} [\w-]+:", part):  # a message the command printed
                    found.append(part)
    return found


def _pages():
    # docs/examples/ is what mkdocs-gallery writes from examples/ (ignored by git, absent from a clean clone):
    # the pages written by hand, not a build's output
    generated = REPO / "docs" / "examples"
    return [REPO / "README.md", *sorted(p for p in (REPO / "docs").rglob("*.md") if generated not in p.parents)]


def _doc_commands():
    rows = []
    for page in _pages():
        rows += [(page.relative_to(REPO).as_posix(), c) for c in _commands(_fenced(page.read_text()))]
    for parser in ALL:  # the examples of each command's --help
        rows += [(f"{parser.prog} --help", c) for c in _commands(_examples(parser))]
    return rows


def _examples(parser) -> list[str]:
    """The lines under 'Examples:' in a command's --help, continuation lines joined, a note in brackets cut."""
    lines, inside, joined = [], False, ""
    for line in "\n".join(t for t in (parser.description, parser.epilog) if t).splitlines():
        if re.fullmatch(r"\s*examples?:\s*", line, flags=re.I):
            inside = True
        elif inside and not line.strip():
            inside = False
        elif inside:
            joined = f"{joined} {line.strip()}" if joined else line.strip()
            if joined.endswith("\\"):
                joined = joined[:-1]
                continue
            lines.append(re.sub(r"\s{2,}\(.*\)$", "", joined))
            joined = ""
    return lines


DOC_COMMANDS = _doc_commands()


def _argv(command: str) -> tuple[str, list[str]]:
    prog = next(p for p in PROGRAMS if command.startswith(p + " "))
    words = [w for w in shlex.split(command[len(prog):]) if w != "..."]
    return prog, words


def test_the_docs_show_command_lines():
    pages = {page for page, _ in DOC_COMMANDS}
    assert len(DOC_COMMANDS) > 80 and {"README.md", "docs/guide/convert.md", "lenslab tonemap --help"} <= pages


@pytest.mark.parametrize("page,command", DOC_COMMANDS, ids=[f"{p}: {c[:60]}" for p, c in DOC_COMMANDS])
def test_every_documented_command_line_parses(page, command):
    prog, argv = _argv(command)
    code, err = _exit(PROGRAMS[prog]().parse_args, argv)
    assert code == 0, f"{page}: {command}\n{err}"


def _inline_commands() -> list[tuple[str, str]]:
    """Commands quoted in the pages' running text (`lenslab bench warp --only-threads`): often a fragment."""
    rows = []
    for page in _pages():
        text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
        for span in re.findall(r"`([^`\n]+)`", text):
            rows += [(page.relative_to(REPO).as_posix(), c) for c in _commands([span])]
    return rows


INLINE = _inline_commands()


@pytest.mark.parametrize("page,command", INLINE, ids=[f"{p}: {c[:60]}" for p, c in INLINE])
def test_every_option_quoted_in_the_text_is_a_whole_option(page, command):
    """A fragment need not parse, but each ``--option`` it shows is spelled whole for its command."""
    prog, argv = _argv(command)
    parser = PROGRAMS[prog]()
    for word in argv:
        subs = next((a.choices for a in parser._actions if isinstance(a, argparse._SubParsersAction)), {})
        if word in subs:
            parser = subs[word]
        elif word.startswith("--"):
            assert word.partition("=")[0] in parser._option_string_actions, f"{page}: {command}: {word}"
