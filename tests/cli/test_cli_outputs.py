"""The output policy, for every command of every entry point (derived from the parsers).

Every command that writes is run against an output that already exists (no --overwrite: one error line,
exit code 1) and against its own input (with --overwrite, by the same path and through a symbolic link: a
usage error, one line and exit code 2 as the brief gives usage errors, before the input is read), and the
file's bytes are unchanged. A command added later fails
``test_every_command_is_classified`` until it has a row here.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from tests.cli_entry_points import all_commands, run

KEEP = b"an earlier result the user wants to keep\n"

# Commands that write no file (they print): nothing to refuse.
PRINTS = {"lenslab info", "lenslab lenses", "lenslab fit lens", "lenslab fit points", "lenslab fit tone",
          "lenslab camera show", "tracer bench", "tracer scenes"}


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    from lenslab.io import write

    d = tmp_path_factory.mktemp("outputs")
    rng = np.random.default_rng(1)
    pano = rng.uniform(0.0, 4.0, (32, 64, 3)).astype(np.float32)
    write(d / "pano.pfm", pano)
    write(d / "pano.exr", pano)
    (d / "hdri").mkdir()
    write(d / "hdri" / "sky.exr", pano)
    (d / "cam.toml").write_text("[lens]\nmodel = \"fisheye\"\nsize = [64, 64]\nfov = 180.0\n")
    for name in ("existing.exr", "existing.png", "existing.jpg", "existing.json", "existing.toml"):
        (d / name).write_bytes(KEEP)
    for folder, name in (("demo", "notes.txt"), ("report", "results.json"), ("page", "index.html")):
        (d / folder).mkdir()
        (d / folder / name).write_bytes(KEEP)
    return d


def _existing(d: Path) -> dict[str, tuple[list[str], Path]]:
    """command -> (arguments that aim at an existing output, that output)."""
    json_ = d / "existing.json"
    cases = {
        "lenslab convert": (["--to", "exr", str(d / "pano.pfm"), "-o", str(d / "existing.exr")], d / "existing.exr"),
        "lenslab warp": ([str(d / "pano.pfm"), "-o", str(d / "existing.exr"), "--to", "fisheye:fov=180"],
                         d / "existing.exr"),
        "lenslab stmap": (["-o", str(d / "existing.exr"), "--from", "equirect", "--to", "fisheye:fov=180",
                           "--size", "16x16"], d / "existing.exr"),
        "lenslab tonemap": ([str(d / "pano.pfm"), "-o", str(d / "existing.png")], d / "existing.png"),
        "lenslab curves": (["-o", str(d / "existing.png")], d / "existing.png"),
        "lenslab compare-tones": ([str(d / "pano.pfm"), "-o", str(d / "existing.jpg")], d / "existing.jpg"),
        "lenslab camera convert": ([str(d / "cam.toml"), "-o", str(d / "existing.toml")], d / "existing.toml"),
        "lenslab diff": ([str(d / "pano.exr"), str(d / "pano.pfm"), "-o", str(d / "existing.exr")], d / "existing.exr"),
        "lenslab demo": (["-o", str(d / "demo"), "--quiet"], d / "demo" / "notes.txt"),
        "lenslab validate": (["--scene", "analytic", "-o", str(d / "report"), "-q"], d / "report" / "results.json"),
        "tracer render": (["--scene", "cornell", "--size", "8x8", "--spp", "1", "-o", str(d / "existing.exr"), "-q"],
                          d / "existing.exr"),
        "python -m gallery": ([str(d / "page"), "--hdri", str(d / "hdri"), "--quiet"], d / "page" / "index.html"),
    }
    for c in all_commands():
        if c.name.startswith("lenslab bench "):  # refused before the benchmark runs
            cases[c.name] = (["--json", str(json_)], json_)
    return cases


def _own_input(d: Path, link: bool) -> dict[str, tuple[list[str], Path]]:
    """command -> (arguments whose output is the command's own input, that input), with --overwrite.

    With ``link``, the output is a symbolic link to the input (or the input a link to the output)."""
    pfm, exr = d / "pano.pfm", d / "pano.exr"
    via_pfm, via_exr = (d / "link-to-pano.pfm", d / "link-to-pano.exr") if link else (pfm, exr)
    cases = {
        "lenslab convert": (["--to", "exr", str(exr), "-o", str(via_exr), "--overwrite"], exr),
        "lenslab warp": ([str(exr), "-o", str(via_exr), "--to", "fisheye:fov=180", "--overwrite"], exr),
        "lenslab tonemap": ([str(via_pfm), "-o", str(pfm), "--overwrite"], pfm),
        "lenslab compare-tones": ([str(pfm), "-o", str(via_pfm), "--overwrite"], pfm),
        "lenslab camera convert": ([str(d / "cam.toml"), "-o", str(d / ("link-to-cam.toml" if link else "cam.toml")),
                                    "--overwrite"], d / "cam.toml"),
        "lenslab diff": ([str(exr), str(pfm), "-o", str(via_exr), "--overwrite"], exr),
        "tracer render": (["--scene", "sky", "--env", str(exr), "--size", "8x8", "--spp", "1", "-o", str(via_exr),
                           "--overwrite", "-q"], exr),
    }
    if not link:  # folders: the output folder is an input folder
        cases["lenslab demo"] = (["-o", str(d / "hdri"), "--hdri", str(d / "hdri"), "--overwrite", "--quiet"],
                                 d / "hdri" / "sky.exr")
        cases["python -m gallery"] = ([str(d / "hdri"), "--hdri", str(d / "hdri"), "--overwrite", "--quiet"],
                                      d / "hdri" / "sky.exr")
    return cases


# Writers with no input a user could name as their output (reason given).
NO_INPUT_TO_WRITE_OVER = {
    "lenslab stmap": "its inputs are lens specs or calibration files, never the .exr map it writes",
    "lenslab curves": "it reads nothing",
    "lenslab validate": "it renders its own inputs",
    "lenslab bench": "it measures its own data",
}


#: commands whose refusal has another exit code than 1 (reason given)
REFUSAL_CODE = {
    "lenslab diff": (4, "idiff's exit codes: 1 is WARNING, 4 a file that cannot be read or written"),
}


def _commands() -> dict:
    return {c.name: c for c in all_commands()}


def test_every_command_is_classified(tmp_path):
    names = set(_commands())
    existing = set(_existing(tmp_path))
    assert names == existing | PRINTS, sorted(names ^ (existing | PRINTS))
    own = set(_own_input(tmp_path, link=False))
    for name in existing - own:
        assert name in NO_INPUT_TO_WRITE_OVER or name.rpartition(" ")[0] in NO_INPUT_TO_WRITE_OVER, name


@pytest.mark.parametrize("name", sorted(set(_existing(Path("/nonexistent")))))
def test_an_existing_output_is_refused(work, name):
    args, protected = _existing(work)[name]
    before = protected.read_bytes()
    code, _, err = run(_commands()[name], args)
    assert code == REFUSAL_CODE.get(name, (1,))[0], (name, err)
    assert "already exists" in err or "not empty" in err, err
    assert len(err.strip().splitlines()) <= 2 and "Traceback" not in err  # the error, and a batch's summary
    assert protected.read_bytes() == before == KEEP


OWN = [(name, link) for link in (False, True) for name in sorted(_own_input(Path("/nonexistent"), link))]


@pytest.mark.parametrize("name,link", OWN, ids=[f"{n}, {'through a link' if k else 'same path'}" for n, k in OWN])
def test_an_input_is_never_written_over(work, name, link):
    args, protected = _own_input(work, link)[name]
    for target, source in (("link-to-pano.pfm", "pano.pfm"), ("link-to-pano.exr", "pano.exr"),
                           ("link-to-cam.toml", "cam.toml")):
        if not (work / target).is_symlink():
            os.symlink(work / source, work / target)
    before = protected.read_bytes()
    code, _, err = run(_commands()[name], args)
    assert code == 2, (name, err)  # a usage error, whatever the command's other codes (diff's 4 included)
    assert len(err.strip().splitlines()) == 1 and "is an input of " in err, err
    assert "Traceback" not in err
    assert protected.read_bytes() == before
    assert not [p for p in work.rglob(".*tmp*")], "a temporary file was left behind"


#: batch forms whose planned outputs include one of their inputs: (arguments, the input written over)
def _batch_own_input(d: Path) -> dict[str, list[str]]:
    return {
        "lenslab convert": ["--to", "exr", str(d), "-o", str(d), "--overwrite"],
        "lenslab warp": [str(d), "-o", str(d), "--to", "fisheye:fov=180", "--format", "exr", "--overwrite"],
        "lenslab tonemap": [str(d), "-o", str(d), "--format", "exr", "--overwrite"],
    }


@pytest.mark.parametrize("name", sorted(_batch_own_input(Path("/nonexistent"))))
def test_a_batch_that_would_write_over_an_input_is_a_usage_error_before_any_read(tmp_path, name):
    """The inputs are not images at all: had any been read, the error would name what is wrong with it
    (exit 1); the one line is the usage error found from the names alone."""
    for f in ("a.exr", "b.exr"):
        (tmp_path / f).write_bytes(KEEP)
    code, _, err = run(_commands()[name], _batch_own_input(tmp_path)[name])
    assert code == 2, err
    assert err.strip().splitlines() == [f"{name}: error: {tmp_path / 'a.exr'}: is an input of this command; it is "
                                        "never written over, even with --overwrite: choose another output name"], err
    assert (tmp_path / "a.exr").read_bytes() == (tmp_path / "b.exr").read_bytes() == KEEP


#: command -> (the input's name, arguments before it, the option that names it when it is not positional)
ONE_FILE = {
    "lenslab convert": ("a.exr", ["--to", "exr"], None),
    "lenslab warp": ("a.exr", ["--to", "fisheye:fov=180"], None),
    "lenslab tonemap": ("a.exr", [], None),
    "lenslab compare-tones": ("a.exr", [], None),
    "lenslab diff": ("a.exr", ["{src}"], None),
    "lenslab camera convert": ("cam.toml", [], None),
    "tracer render": ("a.exr", ["--scene", "sky", "--size", "8x8", "--spp", "1", "-q"], "--env"),
}


@pytest.mark.parametrize("name", sorted(ONE_FILE))
def test_one_file_named_as_its_own_output_is_refused_before_it_is_read(tmp_path, name):
    file, extra, option = ONE_FILE[name]
    src = tmp_path / file
    src.write_bytes(KEEP)  # not an image or a camera: reading it would fail with another message and exit 1
    extra = [str(src) if a == "{src}" else a for a in extra]
    named = [option, str(src)] if option else [str(src)]
    code, _, err = run(_commands()[name], [*extra, *named, "-o", str(src), "--overwrite"])
    assert code == 2, err
    assert err.strip().splitlines() == [f"{name}: error: {src}: is an input of this command; it is never written "
                                        "over, even with --overwrite: choose another output name"], err
    assert src.read_bytes() == KEEP
