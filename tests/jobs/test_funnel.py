"""The one error funnel: every failure is one line naming the file and the cause (traceback only under
--debug), and --overwrite never replaces what is not a regular file."""

from __future__ import annotations

import os
import stat
import subprocess
import sys

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write
from lenslab.jobs.funnel import exit_code, one_line, run_command


@pytest.fixture()
def pano(tmp_path):
    path = tmp_path / "pano.exr"
    write(path, np.full((8, 16, 3), 0.5, np.float32))
    return path


@pytest.mark.parametrize("command", [["convert", "--to", "exr"], ["warp", "--to", "fisheye"], ["tonemap"]])
def test_overwrite_never_replaces_a_fifo(tmp_path, pano, command, capsys):
    fifo = tmp_path / "x.exr" if command[0] != "tonemap" else tmp_path / "x.png"
    os.mkfifo(fifo)
    status = main([command[0], str(pano), "-o", str(fifo), *command[1:], "--overwrite"])
    err = capsys.readouterr().err
    assert status == 1, err
    assert err.count("\n") == 1 and str(fifo) in err and "not a regular file" in err, err
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)  # still the FIFO, never opened for writing


def test_overwrite_in_a_batch_fails_the_fifo_alone(tmp_path, pano, capsys):
    other = tmp_path / "other.exr"
    write(other, np.full((8, 16, 3), 0.25, np.float32))
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / "pano.pfm")
    status = main(["convert", str(pano), str(other), "--to", "pfm", "-o", str(out), "--overwrite"])
    err = capsys.readouterr().err
    assert status == 1
    assert ": error: " in err and "pano.pfm" in err and "converted 1 of 2" in err
    assert stat.S_ISFIFO(os.stat(out / "pano.pfm").st_mode)
    assert (out / "other.pfm").read_bytes().startswith(b"PF\n")  # PFM's colour magic


def test_overwrite_never_writes_to_a_device(tmp_path, pano, capsys):
    link = tmp_path / "x.pfm"
    os.symlink("/dev/null", link)  # an output name that leads to a device
    status = main(["convert", str(pano), "--to", "pfm", "-o", str(link), "--overwrite"])
    err = capsys.readouterr().err
    assert status == 1 and "not a regular file" in err, err
    assert os.readlink(link) == "/dev/null"


def test_an_unexpected_error_is_one_line_with_its_type_and_the_traceback_only_under_debug(capsys):
    def broken():
        raise RecursionError("maximum recursion depth exceeded\nwhile calling a Python object")

    assert run_command("lenslab x", broken) == 1
    err = capsys.readouterr().err
    assert err == "lenslab x: error: RecursionError: maximum recursion depth exceeded\n"
    assert run_command("lenslab x", broken, debug=True) == 1
    err = capsys.readouterr().err
    assert err.startswith("Traceback") and err.endswith("lenslab x: error: RecursionError: maximum recursion depth "
                                                        "exceeded\n")


def test_a_message_is_cut_and_names_its_file():
    from lenslab.errors import FormatError, LensError, UsageError

    exc = FormatError("x" * 10_000)
    exc.lenslab_file = "big.yaml"
    text = one_line(exc)
    assert text.startswith("big.yaml: xxx") and len(text) == 400 and text.endswith("...")
    assert exit_code(UsageError("bad")) == 2
    assert exit_code(LensError("unknown lens")) == 2  # a spec given on the command line
    read = LensError("unknown lens")
    read.lenslab_file = "cam.yaml"
    assert exit_code(read) == 1  # the same error from a file: a failed input
    assert one_line(MemoryError()).startswith("out of memory")
    assert one_line(FileNotFoundError(2, "No such file or directory", "a.exr")) == "a.exr: no such file or directory"


def test_a_closed_pipe_ends_quietly(pano):
    proc = subprocess.run(f"{sys.executable} -m lenslab info {pano} {pano} {pano} | head -c 1", shell=True,
                          capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == ""


@pytest.mark.parametrize("command", [["convert", "--to", "exr"], ["warp", "--to", "fisheye"], ["tonemap"]])
def test_one_damaged_input_is_one_line_naming_it(tmp_path, command, capsys):
    bad = tmp_path / "bad.exr"
    bad.write_bytes(b"v/1\x01" + b"\x00" * 64)  # OpenEXR's magic number, then nothing an EXR holds
    out = tmp_path / ("out.png" if command[0] == "tonemap" else "out.exr")
    status = main([command[0], str(bad), "-o", str(out), *command[1:]])
    err = capsys.readouterr().err
    assert status == 1, err
    assert err.count("\n") == 1 and str(bad) in err and "Traceback" not in err, err
    assert not out.exists() and not [p for p in tmp_path.iterdir() if ".tmp-" in p.name]
