"""The cases of the output and exit-code policy that users met: each one line, the documented code, no debris."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.fixture
def folder(tmp_path):
    rng = np.random.default_rng(3)
    (tmp_path / "hdri").mkdir()
    for name in ("a", "b"):
        write(tmp_path / "hdri" / f"{name}.pfm", rng.uniform(0, 2, (16, 32, 3)).astype(np.float32))
    return tmp_path


def _run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's usage errors
        code = exc.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("bad", [["--to", "fisheye:fvo=180"], ["--to", "fisheye:fov=180", "--tone", "nope"],
                                 ["--to", "fisheye:fov=180", "--size", "-100x100"]],
                         ids=["misspelt lens parameter", "unknown tone curve", "negative size"])
def test_a_batch_with_a_bad_setting_stops_once_and_makes_no_folder(folder, capsys, bad):
    code, err = _run(capsys, "warp", str(folder / "hdri"), "-o", str(folder / "out"), *bad)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "usage:" not in err  # one line, not once per file
    assert not (folder / "out").exists()


def test_counts_out_of_range_are_usage_errors(folder, capsys):
    code, err = _run(capsys, "convert", str(folder / "hdri"), "--to", "exr", "-o", str(folder / "out"), "--jobs", "-3")
    assert code == 2 and "must be at least 0" in err and len(err.strip().splitlines()) == 1
    assert not (folder / "out").exists()


def test_a_batch_with_a_bad_file_reports_it_and_exits_1(folder, capsys):
    (folder / "hdri" / "broken.pfm").write_bytes(b"PF\n32 16\n-1.0\n")  # a header, no pixels
    code, err = _run(capsys, "convert", str(folder / "hdri"), "--to", "exr", "-o", str(folder / "out"))
    assert code == 1
    assert "broken.pfm" in err and "converted 2 of 3 file(s) to EXR; 1 failed" in err
    assert sorted(p.name for p in (folder / "out").iterdir()) == ["a.exr", "b.exr"]


def test_a_closed_pipe_ends_quietly(folder):
    # `lenslab info F G | head -1`: the reader goes away after one line
    cmd = (f"{sys.executable} -m lenslab info {folder / 'hdri' / 'a.pfm'} {folder / 'hdri' / 'b.pfm'} "
           "--json | head -c 1")
    res = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""


def test_repairs_say_how_many_and_how_large_once_per_file(tmp_path, capsys):
    img = np.full((8, 8, 3), 0.5, np.float32)
    img[0, :, 0] = -3e-2  # eight negative values: real negative light, not a codec's undershoot
    write(tmp_path / "in.pfm", img)
    code, err = _run(capsys, "tonemap", str(tmp_path / "in.pfm"), "-o", str(tmp_path / "out.png"), "-q")
    assert code == 0
    assert err.count("repaired") == 1
    assert "8 negative values, down to -0.03, set to 0 (of 192 values)" in err


def test_slight_negatives_of_a_batch_are_one_summary_line(tmp_path, capsys):
    # DWAB-sized undershoots (-4e-4, within one half-float step at white, 2^-10) in every file of a batch:
    # one line for the command, no note per file and no Python warning
    import warnings

    for i in range(3):
        img = np.full((8, 8, 3), 0.5, np.float32)
        img[i, :4, 1] = -4e-4
        write(tmp_path / f"in{i}.pfm", img)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a Python warning would fail here
        code, err = _run(capsys, "tonemap", *(str(tmp_path / f"in{i}.pfm") for i in range(3)),
                         "-o", str(tmp_path / "out"), "--format", "png", "-q")
    assert code == 0, err
    lines = [ln for ln in err.splitlines() if "negative" in ln]
    assert lines == ["lenslab tonemap: note: 12 slightly negative values (down to -0.0004, a lossy codec's or "
                     "filter's undershoot) set to 0 in 3 files"]


@pytest.mark.shared_data
def test_numpy_warnings_never_reach_the_user(shared_data, tmp_path):
    # every half value, NaN and infinities included: the repairs are reported, NumPy's notes are not
    # (a real process, with Python's default warning filters: pytest would catch the warnings itself)
    src = shared_data / "formats" / "openexr-images" / "TestImages" / "AllHalfValues.exr"
    for argv in (["convert", str(src), "--to", "jpg", "-o", str(tmp_path / "a.jpg")],
                 ["tonemap", str(src), "-o", str(tmp_path / "b.png")],
                 ["warp", str(src), "-o", str(tmp_path / "c.exr"), "--from", "perspective:fov=60",
                  "--to", "fisheye:fov=90", "--size", "32x32"],
                 ["info", str(src)]):
        res = subprocess.run([sys.executable, "-W", "default", "-m", "lenslab", *argv], capture_output=True, text=True)
        assert res.returncode == 0, res.stderr
        assert "encountered" not in res.stderr and "Warning" not in res.stderr, res.stderr


@pytest.mark.parametrize("raised,code", [(KeyboardInterrupt(), 130), (BrokenPipeError(32, "Broken pipe"), 0),
                                         ("lens", 2), ("format", 1), (FileNotFoundError(2, "No such file"), 1)],
                         ids=["interrupted", "closed pipe", "bad lens spec", "bad file", "missing file"])
def test_exit_codes_of_the_policy(raised, code, capsys):
    from lenslab.jobs.funnel import run_command
    from lenslab.errors import FormatError, LensError

    exc = {"lens": LensError("fisheye: unknown parameter(s) fvo"), "format": FormatError("x.exr: truncated")}.get(
        raised, raised)

    def fail():
        raise exc

    if code == 0:  # the closed pipe points stdout at /dev/null: give it a file of its own
        import os

        saved = os.dup(1)
        try:
            assert run_command("lenslab x", fail) == 0
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    else:
        assert run_command("lenslab x", fail) == code
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == (0 if code == 0 else 1), err  # quiet, or one line
