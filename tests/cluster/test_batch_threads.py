"""Batches on this machine run several files at once on threads (``--jobs``, default one per core):
each file's output and notes are what a one-at-a-time run gives, whatever the number of threads."""

from __future__ import annotations

import re
import threading

import cv2
import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main
from lenslab.cluster.threads import recorded_warnings, run_threads

N = 10


@pytest.fixture
def frames(tmp_path):
    """Ten small HDR frames; frame i (odd i) has 4 i values of -(i + 1) * 1e-5 for the tone curve to repair,
    in the middle of the frame (what a fisheye looking forward sees)."""
    d = tmp_path / "in"
    d.mkdir()
    rng = np.random.default_rng(7)
    for i in range(N):
        image = (rng.random((32, 64, 3)) * 3).astype(np.float32)
        if i % 2:
            image[16 - i // 2:16 - i // 2 + i, 30:34, 0] = -(i + 1) * 0.2  # real negatives (beyond 2^-5 of their block): a note per file
        lio.write(d / f"f{i:02d}.pfm", image)
    return d


def _notes(err: str) -> dict[str, str]:
    return dict(re.findall(r"note: \S*?(f\d\d)\.pfm: tone mapping repaired (\d+) ", err))


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["tonemap", "--curve", "hable", "--to", "png"],
                                     ["warp", "--to", "fisheye:fov=180", "--size", "48x48", "--format", "png"]])
def test_threads_give_the_bytes_and_notes_of_one_at_a_time(frames, tmp_path, capsys, command):
    if command[0] == "tonemap":  # tonemap names the format by the output folder's files
        command = ["tonemap", "--curve", "hable", "--format", "png"]
    runs = {}
    for jobs in (1, 3):
        out = tmp_path / f"out{jobs}"
        rc = main([command[0], str(frames), "-o", str(out), *command[1:], "--jobs", str(jobs)])
        err = capsys.readouterr().err
        assert rc == 0, err
        runs[jobs] = ({p.name: p.read_bytes() for p in sorted(out.iterdir())}, _notes(err))
    assert runs[3] == runs[1]
    files, notes = runs[1]
    assert len(files) == N
    if command[0] != "warp":
        # each note names its own file and that file's count: the frame-i repair is of 4 i values
        assert notes == {f"f{i:02d}": str(4 * i) for i in range(1, N, 2)}
    else:
        # bilinear taps average a thin block of negatives with its positive neighbours: the big blocks
        # survive the warp, and no frame without negatives gets a note
        assert {"f07", "f09"} <= set(notes) <= {f"f{i:02d}" for i in range(1, N, 2)}
    # cv2 reads what the threads wrote as a whole 8-bit PNG of the asked size
    png = cv2.imread(str(tmp_path / "out3" / sorted(files)[0]), cv2.IMREAD_UNCHANGED)
    assert png is not None and png.dtype == np.uint8 and png.shape[0] in (32, 48)


def test_run_threads_keeps_order_and_each_threads_warnings():
    import warnings

    seen = []

    def work(i):
        with recorded_warnings() as caught:
            for _ in range(i % 3):
                warnings.warn(f"job {i}")
        return i, threading.current_thread().name, [str(w.message) for w in caught]

    out = run_threads(work, range(40), 4, seen.append)
    assert [r[0] for r in out] == list(range(40))
    assert sorted(r[0] for r in seen) == list(range(40))
    for i, _, messages in out:  # "always": a repeated warning is recorded each time, and only by its thread
        assert messages == [f"job {i}"] * (i % 3)
    assert len({name for _, name, _ in out}) > 1


def test_one_thread_records_like_catch_warnings():
    import warnings

    with recorded_warnings() as caught:
        warnings.warn("once")
        warnings.warn("once")
    assert [str(w.message) for w in caught] == ["once", "once"]


def test_the_default_runs_as_many_files_at_once_as_the_memory_holds(monkeypatch):
    """The first file's growth of the peak memory bounds the files at once: with room for one file and
    a half, the others run one at a time; with room for many, on every thread."""
    from lenslab.cluster import threads as th

    assert th._peak_rss() > 10 << 20  # the kernel's ru_maxrss, in bytes: this process holds NumPy at least
    assert th.available_memory() > 0  # /proc/meminfo on Linux
    per_file = 48 << 20
    peaks = iter([1 << 30, (1 << 30) + per_file])  # before and after the first file
    monkeypatch.setattr(th, "_peak_rss", lambda: next(peaks))
    monkeypatch.setattr(th, "available_memory", lambda: int(1.5 * per_file / 0.7))

    def work(i):
        return i, threading.current_thread().name

    out = run_threads(work, range(6), 3, first_alone=True, fit_memory=True)
    assert [r[0] for r in out] == list(range(6))
    assert {name for _, name in out} == {threading.current_thread().name}  # one at a time, here
    assert th.memory_bound(3, per_file, 100 * per_file) == 3
    assert th.memory_bound(3, per_file, None) == 3  # unknown memory: no bound
    assert th.memory_bound(8, 10 * per_file, 20 * per_file) == 1  # 70% of 20 holds one file of 10
    assert th.memory_bound(8, 10 * per_file, 60 * per_file) == 4
