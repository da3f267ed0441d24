"""``lenslab info`` of a clip whose container does not count its frames (Matroska: no frame count in its header)
gives the count its duration and rate make, said as such, where it said "0 frames" of a clip of 48."""

from __future__ import annotations

import json
import shutil
import subprocess

import pytest

pytestmark = pytest.mark.skipif(shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None,
                                reason="needs Debian's ffmpeg (installed in CI)")


def counted_by_ffprobe(path) -> int:
    """ffprobe's count of the frames it decodes (``-count_frames``)."""
    shown = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=nb_read_frames",
                            "-of", "json", str(path)], capture_output=True, text=True, check=True).stdout
    return int(json.loads(shown)["streams"][0]["nb_read_frames"])


def test_a_matroska_clip_is_said_to_hold_about_the_frames_ffprobe_counts(tmp_path, capsys):
    clip = tmp_path / "c.mkv"
    subprocess.run(["ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc2=size=64x32:rate=24", "-t", "2",
                    "-c:v", "ffv1", str(clip)], check=True)
    from lenslab.cli.main import main

    assert main(["info", str(clip)]) == 0
    shown = capsys.readouterr().out
    assert f"about {counted_by_ffprobe(clip)} frames (from its duration" in shown, shown
    assert " 0 frames" not in shown, shown


def test_an_mp4_clip_gives_the_count_its_header_holds(tmp_path, capsys):
    clip = tmp_path / "c.mp4"
    subprocess.run(["ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc2=size=64x32:rate=24", "-t", "1",
                    "-pix_fmt", "yuv420p", "-c:v", "libx264", str(clip)], check=True)
    from lenslab.cli.main import main

    assert main(["info", str(clip)]) == 0
    assert f", {counted_by_ffprobe(clip)} frames," in capsys.readouterr().out
