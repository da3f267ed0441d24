"""A truncated EXR gives one line (a FormatError naming the chunk and the byte counts) and nothing from the
library on stderr; files that are whole pass, with every compression lenslab writes."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import io
from lenslab.errors import FormatError


@pytest.fixture
def whole(tmp_path):
    img = np.random.default_rng(0).uniform(0, 4, (70, 40, 3)).astype(np.float32)  # ZIP: 16 lines a chunk, 5 chunks
    path = tmp_path / "whole.exr"
    io.write(path, img, compression="zip")
    return path, img


@pytest.mark.parametrize("keep", [20, 300, 0.5, -1])
def test_a_truncated_file_fails_in_one_line_and_the_library_stays_quiet(whole, tmp_path, capfd, keep):
    path, _ = whole
    data = path.read_bytes()
    n = int(len(data) * keep) if isinstance(keep, float) else (keep if keep > 0 else len(data) + keep)
    cut = tmp_path / "cut.exr"
    cut.write_bytes(data[:n])
    capfd.readouterr()
    with pytest.raises(FormatError) as err:
        io.read(cut)
    text = str(err.value)
    assert "\n" not in text and str(cut) in text and ("truncated" in text or "damaged" in text)
    if keep == -1:  # one byte short: the last chunk, named with the byte counts
        assert f"chunk 5 of 5 ends at byte {len(data)} but the file has {n} bytes" in text
    assert capfd.readouterr().err == ""  # nothing from OpenEXR's core on stderr


@pytest.mark.parametrize("compression", ["none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"])
def test_whole_files_pass_with_every_compression(tmp_path, compression, capfd):
    import OpenEXR

    img = np.random.default_rng(1).uniform(0, 4, (300, 17, 3)).astype(np.float32)
    path = tmp_path / f"{compression}.exr"
    io.write(path, img, compression=compression)
    got, _ = io.read(path)
    ref = OpenEXR.File(str(path)).parts[0].channels  # the library's own reading of the same file
    key = "RGB" if "RGB" in ref else None
    expect = ref[key].pixels if key else np.stack([ref[c].pixels for c in "RGB"], axis=-1)
    np.testing.assert_array_equal(got[..., :3], expect.astype(np.float32))


def test_a_damaged_file_leaves_info_json_clean(whole, tmp_path):
    # the chunk table is whole but a chunk's data is not: OpenEXR itself finds it and prints its own warning on
    # standard output, which `lenslab info --json` must keep out of its report (a subprocess: the library writes
    # to the file descriptor, below Python's sys.stdout)
    import json
    import subprocess
    import sys

    path, _ = whole
    data = bytearray(path.read_bytes())
    mid = len(data) // 2
    data[mid:mid + 64] = bytes(64)
    bad = tmp_path / "garbled.exr"
    bad.write_bytes(bytes(data))
    run = subprocess.run([sys.executable, "-m", "lenslab", "info", "--json", str(path), str(bad)],
                         capture_output=True, text=True)
    assert run.returncode == 1
    report = json.loads(run.stdout)  # nothing but the JSON on standard output
    assert report[0]["file"] == str(path) and "error" not in report[0]
    assert report[1]["file"] == str(bad) and "the file is damaged" in report[1]["error"]
    assert "index out of range" not in run.stderr
