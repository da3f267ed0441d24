"""What the names alone settle is a usage error (exit status 2, one line), found before any input is read:
two inputs that would be written to one output, and an output that is an input (also when two inputs would
both be written to it). The inputs here hold bytes that are no image: had a command read one, it would have
failed that input (exit status 1) instead. Nothing is made: no output folder, and the inputs keep their bytes.
"""

from __future__ import annotations

import os

import pytest

from lenslab.cli.main import main

JUNK = b"not an image at all\n" * 4  # no format reads this: a read would fail the input


@pytest.fixture
def two(tmp_path, monkeypatch):
    """a.exr and a.png in the working folder (relative names, as a user types them)."""
    monkeypatch.chdir(tmp_path)
    for name in ("a.exr", "a.png"):
        (tmp_path / name).write_bytes(JUNK)
    return tmp_path


#: each batch command with the options that make its outputs JPEG, or the input's own format (EXR, PNG)
COMMANDS = {
    "convert": (["--to", "jpg"], ["--to", "exr"], ["--to", "png"], "convert"),
    "warp": (["--to", "equirect", "--format", "jpg"], ["--to", "equirect", "--format", "exr"],
             ["--to", "equirect", "--format", "png"], "warp"),
    "tonemap": (["--format", "jpg"], ["--format", "exr"], ["--format", "png"], "tone-map"),
}


def _run(capsys, argv):
    code = main(argv)
    return code, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("command", list(COMMANDS))
def test_two_inputs_written_to_one_output_is_a_usage_error(two, capsys, command):
    to_jpg, _, _, verb = COMMANDS[command]
    code, lines = _run(capsys, [command, "a.exr", "a.png", *to_jpg, "-o", "out/"])
    assert code == 2, lines
    assert lines == [f"lenslab {command}: error: a.png and a.exr would both be written to "
                     f"{os.path.join('out', 'a.jpg')}; {verb} them separately"]
    assert not (two / "out").exists()  # no folder made for a batch that cannot start


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("case", ["two files, -o . --overwrite", "the folder ."])
def test_a_shared_output_that_is_an_input_is_named_as_an_input(two, capsys, command, case):
    """``a.exr a.png -o .`` to EXR: both would be written to a.exr, which is an input; the input is the
    cause to name, the same line as for one input named as its own output."""
    _, to_exr, to_png, _ = COMMANDS[command]
    if case == "the folder .":  # a.png is an input, and a.exr would be written to it too
        argv, hit = [command, ".", *to_png, *(["-o", "."] if command != "convert" else [])], "a.png"
    else:
        argv, hit = [command, "a.exr", "a.png", *to_exr, "-o", ".", "--overwrite"], "a.exr"
    code, lines = _run(capsys, argv)
    assert code == 2, lines
    assert lines == [f"lenslab {command}: error: {hit}: is an input of this command; it is never written over, "
                     "even with --overwrite: choose another output name"]
    assert (two / "a.exr").read_bytes() == JUNK and (two / "a.png").read_bytes() == JUNK
