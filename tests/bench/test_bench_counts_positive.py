"""A benchmark's counts (``--repeat``, ``--images``, ``--frames``, ``--size``, ``--spp``...) are at least 1: 0 or
a negative number is a usage error in one line (exit status 2) before anything is measured, never a run
that reports "best of 0" figures after minutes of work on a shared machine."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main as lenslab
from tracer.cli import main as tracer


@pytest.mark.parametrize("main, argv, prog", [
    (lenslab, ["bench", "warp", "--repeat", "0"], "lenslab bench warp"),
    (lenslab, ["bench", "io", "--repeat", "0"], "lenslab bench io"),
    (lenslab, ["bench", "io", "--images", "-2"], "lenslab bench io"),
    (lenslab, ["bench", "lenses", "--repeat", "0"], "lenslab bench lenses"),
    (lenslab, ["bench", "lenses", "--size", "0"], "lenslab bench lenses"),
    (lenslab, ["bench", "tone", "--repeat", "0"], "lenslab bench tone"),
    (lenslab, ["bench", "tone", "--threads", "0"], "lenslab bench tone"),
    (lenslab, ["bench", "startup", "--repeat", "0"], "lenslab bench startup"),
    (lenslab, ["bench", "cluster", "--repeat", "0"], "lenslab bench cluster"),
    (lenslab, ["bench", "cluster", "--frames", "0"], "lenslab bench cluster"),
    (lenslab, ["bench", "memory", "--side", "0"], "lenslab bench memory"),
    (tracer, ["bench", "--repeat", "0"], "tracer bench"),
    (tracer, ["bench", "--spp", "0"], "tracer bench"),
    (tracer, ["bench", "--size", "-1"], "tracer bench"),
])
def test_count_below_one_is_a_usage_error(tmp_path, monkeypatch, capsys, main, argv, prog):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert out == "" and len(lines) == 1 and lines[0].startswith(f"{prog}: error: argument --"), (out, lines)
    assert list(tmp_path.iterdir()) == []
