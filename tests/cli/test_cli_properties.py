"""Property test of every command: argument lists built from the command's own parser.

For each command of ``lenslab``, ``tracer`` and ``python -m gallery`` (found from the parsers),
hypothesis draws argument lists: each option and positional of the parser with a valid value, a
mangled one (text for a number, a negative size, NaN, an unknown name) or a missing file. Whatever it
draws, the command ends with exit code 0, 1 or 2, never prints a traceback, leaves no temporary file,
never changes an input, and on a usage error (2) changes nothing at all.

Commands whose valid runs take seconds (rendering, benchmarks, fitting, the demo) always get one value
their parser refuses, so they stop at the parser, as a user's typo would; the others run for real on
tiny images. Options that start worker processes (--scheduler) or a browser (--check) are left out.
"""

from __future__ import annotations

import argparse
import hashlib
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.cli_entry_points import all_commands, run

COMMANDS = {c.name: c for c in all_commands()}
SLOW = ("lenslab demo", "lenslab validate", "lenslab bench", "lenslab fit", "tracer render", "tracer bench",
        "python -m gallery")
LEFT_OUT = {"--scheduler", "--scheduler-file", "--check", "--big", "--help"}
EXAMPLES = 10  # per command: ~25 commands x 10 runs, most of them stopped by a parser in milliseconds

INPUTS = ("pano.pfm", "pano.exr", "small.png", "cam.toml", "points.csv", "hdri")
MISSING = ("missing.exr", "no/such/folder/x.pfm", "hdri/missing.exr")
SPECS = ("fisheye:fov=180", "perspective:fov=90", "equirect", "swirl:amount=6", "fisheye:fvo=180",
         "perspective:fov=-3", "nope", "", "fisheye:fov=180,mapping=sideways", "cubemap")
CURVES = ("hable", "aces", "clamp", "reinhard", "nope", "")
MANGLED = ("abc", "", "-3", "0", "nan", "inf", "-100x100", "1e400", "x", "1,2", "big", "%", "-")
EXTENSIONS = (".exr", ".pfm", ".png", ".jpg", ".ppm", ".toml", ".json", ".txt", "", "/")


def _is_slow(name: str) -> bool:
    return name.startswith(SLOW)


def _refused(action: argparse.Action) -> list[str]:
    """The mangled values the parser itself refuses for this option (by its type function or choices)."""
    if action.nargs == 0:
        return []
    out = []
    for text in MANGLED:
        try:
            value = action.type(text) if callable(action.type) else text
        except (argparse.ArgumentTypeError, ValueError, TypeError):
            out.append(text)
            continue
        if action.choices is not None and value not in action.choices:
            out.append(text)
    return out


def _value(action: argparse.Action, draw, mangle: bool) -> str:
    name = action.dest
    if mangle == "refused":
        return draw(st.sampled_from(_refused(action)))
    if mangle:
        return draw(st.sampled_from(MANGLED))
    if action.choices:
        return str(draw(st.sampled_from(sorted(map(str, action.choices)))))
    tname = getattr(action.type, "__name__", "")
    if "size" in tname or name in ("size", "source_size", "amortised_size"):
        return f"{draw(st.integers(1, 12))}x{draw(st.integers(1, 12))}"
    if action.type in (float,) or tname in ("positive_float",):
        return repr(draw(st.floats(-400, 400, allow_nan=False)))
    if action.type is int or tname == "parse":
        return str(draw(st.integers(-2, 4)))
    if name in ("output", "json", "variance_out", "readme_images", "dst", "out"):
        return "out/result" + draw(st.sampled_from(EXTENSIONS))
    if name in ("to", "source", "model", "camera", "from") or "spec" in name:
        return draw(st.sampled_from(SPECS + INPUTS[3:4]))
    if name in ("curve", "tone", "curves"):
        return draw(st.sampled_from(CURVES))
    if name == "scene":
        return draw(st.sampled_from(("cornell", "analytic", "sky", "nowhere")))
    if name == "exposure":
        return draw(st.sampled_from(("0", "1.5", "auto", "-2", "bright")))
    return draw(st.sampled_from(INPUTS + MISSING + MANGLED[:3]))


@st.composite
def argument_lists(draw, command) -> list[str]:
    """Arguments for ``command``, from its parser's actions."""
    actions = [a for a in command.parser._actions
               if not isinstance(a, argparse._HelpAction) and not set(a.option_strings) & LEFT_OUT]
    checked = [a for a in actions if _refused(a)]
    forced = draw(st.sampled_from(checked)) if _is_slow(command.name) and checked else None
    args: list[str] = []
    for a in actions:
        if not a.option_strings:  # positional
            count = {None: 1, "?": draw(st.integers(0, 1)), "*": draw(st.integers(0, 2)),
                     "+": draw(st.integers(1, 2))}.get(a.nargs, a.nargs if isinstance(a.nargs, int) else 1)
            args += [_value(a, draw, "refused" if a is forced else False) for _ in range(count)]
            continue
        if a is not forced and not a.required and not draw(st.booleans()):
            continue
        args.append(draw(st.sampled_from(a.option_strings)))
        if a.nargs == 0:
            continue
        count = a.nargs if isinstance(a.nargs, int) else (0 if a.nargs == "?" and draw(st.booleans()) else 1)
        mangle = "refused" if a is forced else draw(st.integers(0, 4)) == 0
        args += [_value(a, draw, mangle) for _ in range(count)]
    return args


def _make_inputs(d: Path) -> None:
    from lenslab.io import write

    rng = np.random.default_rng(0)
    pano = rng.uniform(0.0, 3.0, (8, 16, 3)).astype(np.float32)
    write(d / "pano.pfm", pano)
    write(d / "pano.exr", pano)
    write(d / "small.png", np.clip(pano / 3, 0, 1))
    (d / "hdri").mkdir()
    write(d / "hdri" / "sky.exr", pano)
    (d / "cam.toml").write_text("[lens]\nmodel = \"fisheye\"\nsize = [16, 16]\nfov = 180.0\n")
    (d / "points.csv").write_text("x,y,dx,dy,dz\n8,8,0,0,1\n4,8,-0.5,0,0.8660254\n12,8,0.5,0,0.8660254\n")


def _snapshot(d: Path) -> dict[str, str]:
    return {str(p.relative_to(d)): (hashlib.sha1(p.read_bytes()).hexdigest() if p.is_file() else "dir")
            for p in sorted(d.rglob("*"))}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_any_argument_list_ends_cleanly(name, monkeypatch):
    command = COMMANDS[name]

    @settings(max_examples=EXAMPLES if not name.startswith("python -m gallery") else 5, deadline=None,
              derandomize=True, suppress_health_check=list(HealthCheck))
    @given(argument_lists(command))
    def check(args):
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            _make_inputs(d)
            monkeypatch.chdir(d)  # relative names in the argument lists resolve here
            before = _snapshot(d)
            code, _, err = run(command, args)
            after = _snapshot(d)
        context = f"{name} {' '.join(args)}\n{err}"
        assert "Traceback" not in err or "--debug" in args, context  # --debug asks for the traceback
        assert code in (0, 1, 2), context
        assert not [k for k in after if Path(k).name.startswith(".") and "tmp" in k], context  # no temporary file
        assert {k: after.get(k) for k in before} == before or "--overwrite" in args, context  # inputs unchanged
        if code == 2:
            assert after == before, context  # a usage error touches nothing
        if code != 0:
            assert err.strip(), context  # a failure says why

    check()
