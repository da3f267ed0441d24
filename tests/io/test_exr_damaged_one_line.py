"""A damaged EXR whose chunk table is whole (so only OpenEXR itself finds the damage) fails in exactly one
line, ``lenslab CMD: error: FILE: cause``: what the library prints on the file descriptors is kept off the
terminal, and lenslab's own lines still come through."""

from __future__ import annotations

import os
import struct
import subprocess
import sys

import numpy as np
import pytest

from lenslab import io
from lenslab.library_output import quiet_library


@pytest.fixture
def damaged(tmp_path):
    img = np.random.default_rng(3).uniform(0, 4, (96, 64, 3)).astype(np.float32)  # ZIP: 16 lines a chunk
    good = tmp_path / "good.exr"
    io.write(good, img, compression="zip")
    data = bytearray(good.read_bytes())
    n = 96 // 16
    # the offset table (n uint64, OpenEXR file layout) sits just before the first chunk it points to
    table = next(p for p in range(8, len(data) - 8 * n)
                 if struct.unpack_from("<Q", data, p)[0] == p + 8 * n)
    first, second = struct.unpack_from("<2Q", data, table)
    for i in range(first + 8 + 4, second, 5):  # garble the first chunk's compressed bytes, not its leader
        data[i] ^= 0x5A
    bad = tmp_path / "bad.exr"
    bad.write_bytes(bytes(data))
    return good, bad


def _library_says(path) -> tuple[int, str]:
    """What OpenEXR itself prints on the descriptors when reading ``path``, in a child process."""
    code = ("import OpenEXR, sys\ntry:\n    OpenEXR.File(sys.argv[1], separate_channels=True).parts[0].channels\n"
            "except Exception:\n    sys.exit(3)\n")
    run = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["tonemap"], ["info"]])
def test_a_damaged_exr_fails_in_exactly_one_line(damaged, tmp_path, command):
    good, bad = damaged
    code, said = _library_says(bad)
    # the outside fact: OpenEXR refuses the file and prints lines of its own when asked directly
    assert code == 3 and "EXR_ERR_" in said and len(said.strip().splitlines()) >= 2
    out = tmp_path / "out"
    out.mkdir()
    args = [*command, str(bad)] + (["-o", str(out)] if command[0] != "info" else [])
    run = subprocess.run([sys.executable, "-m", "lenslab", *args], capture_output=True, text=True)
    assert run.returncode == 1
    lines = (run.stdout if command[0] != "info" else "").splitlines() + run.stderr.splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"lenslab {command[0]}: error: {bad}: ") and "damaged" in lines[0]
    assert "EXR_ERR_CORRUPT_CHUNK" in lines[0]  # the library's first word on it, as the cause


def test_the_good_file_in_the_same_run_still_converts(damaged, tmp_path):
    good, bad = damaged
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", "--to", "pfm", str(good), str(bad), "-o", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 1
    assert [ln for ln in run.stderr.splitlines() if "error" in ln] == [
        ln for ln in run.stderr.splitlines() if ln.startswith(f"lenslab convert: error: {bad}: ")]
    assert len([ln for ln in run.stderr.splitlines() if str(bad) in ln]) == 1
    assert (out / "good.pfm").is_file()


def test_lines_that_are_not_the_library_s_come_through(capfd):
    said: list[str] = []
    with quiet_library(said):
        os.write(2, b"x.exr: (EXR_ERR_CORRUPT_CHUNK) Unable to decompress\n")
        os.write(2, b"lenslab: a note of its own\n")
        os.write(1, b"Warning: Exception raised reading pixel data for part 0 - x\n")
        print("a report line")
    got = capfd.readouterr()
    assert got.err == "lenslab: a note of its own\n" and got.out == "a report line\n"
    assert sorted(said) == ["Warning: Exception raised reading pixel data for part 0 - x",
                            "x.exr: (EXR_ERR_CORRUPT_CHUNK) Unable to decompress"]
