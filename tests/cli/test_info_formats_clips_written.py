"""``lenslab info --formats`` and the formats table of docs/conventions.md say that clips are written (by ``lenslab
warp`` and ``lenslab convert``): the video row said ``write -`` while both commands write .mp4, .mov and .mkv clips.

Outside value: the clip ``lenslab convert`` writes from three frames, as PyAV (FFmpeg) reads it: a video stream of
three frames of the frames' size."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

av = pytest.importorskip("av")
ROOT = Path(__file__).resolve().parents[2]


def test_the_listing_says_clips_are_written(capsys, tmp_path):
    capsys.readouterr()
    assert main(["info", "--formats"]) == 0
    head, *rows = capsys.readouterr().out.splitlines()
    start, end = head.index("write"), head.index("holds")
    video = next(row for row in rows if row.split()[0] == "video")
    assert video[start:end].strip() == "yes"
    assert "write" in video[end:]  # (the note says which commands write them)
    assert main(["info", "--formats", "--json"]) == 0
    import json

    described = {d["name"]: d for d in json.loads(capsys.readouterr().out)}
    assert described["video"]["write"] is True and described["heif"]["write"] is False
    table = (ROOT / "docs" / "conventions.md").read_text(encoding="utf-8").split("<!-- formats:start -->")[1]
    cells = next(line for line in table.splitlines() if line.startswith("| `video`")).split("|")
    assert cells[3].strip() == "yes"
    frames = []
    for i in range(3):
        frames.append(tmp_path / f"f{i}.exr")
        write(frames[-1], np.full((32, 48, 3), 0.2 * (i + 1), np.float32), pixel_type="float")
    clip = tmp_path / "clip.mp4"
    assert main(["convert", *map(str, frames), "-o", str(clip), "-q"]) == 0
    with av.open(str(clip)) as container:
        got = [(f.width, f.height) for f in container.decode(video=0)]
    assert got == [(48, 32)] * 3
