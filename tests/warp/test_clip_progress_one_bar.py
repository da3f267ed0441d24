"""A single clip given to ``lenslab warp`` or ``lenslab convert`` on a terminal shows its bar by frames and nothing
else: no "clip.mp4: reading..." line of the bar of one image's bands (which a clip never starts) in the middle of
it, however long the clip takes.

The patience is made 0 and the clip's work waits until every image bar's timer has fired or been cancelled (a
state, not a duration), so the stray line, when there is one, is on the terminal before the clip's frames; the
terminal's text (a pseudo-terminal's) is the outside judge."""

from __future__ import annotations

import pytest

from lenslab.jobs import progress
from tests.warp.test_warp_progress import on_terminal

HANG_GUARD = 300  # seconds: only against a timer thread that would never end on a broken build


@pytest.fixture
def timers_settled(monkeypatch):
    """Every RowBar made from now on is recorded; ``settle()`` waits until each one's timer is done."""
    made = []
    real = progress.RowBar.__init__

    def init(self, *args, **kwargs):
        real(self, *args, **kwargs)
        made.append(self)

    monkeypatch.setattr(progress.RowBar, "__init__", init)
    monkeypatch.setattr(progress, "PATIENCE", 0.0)

    def settle():
        for bar in made:
            timer = bar.timer
            if timer is not None:
                timer.join(HANG_GUARD)

    return settle


def _wrapped(monkeypatch, module, name: str, settle) -> None:
    real = getattr(module, name)

    def run(*args, **kwargs):
        settle()
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, run)


def test_a_warped_clip_shows_its_frames_bar_alone(tmp_path, monkeypatch, timers_settled):
    import lenslab.jobs.warp.video as warp_video
    from tests.warp.test_video_warp_imports import _clip

    _clip(tmp_path / "clip.mp4")
    _wrapped(monkeypatch, warp_video, "warp_video", timers_settled)
    code, out = on_terminal(monkeypatch, ["warp", str(tmp_path / "clip.mp4"), "-o", str(tmp_path / "fish.mp4"),
                                          "--from", "equirect", "--to", "fisheye:fov=180", "--size", "32x32"])
    assert code == 0
    assert "frame" in out and "reading" not in out and "making the map" not in out, out
    assert out.endswith("warped 1 of 1 file(s) with 1 map(s)\r\n"), out


def test_a_clip_converted_to_frames_shows_its_frames_bar_alone(tmp_path, monkeypatch, timers_settled):
    from lenslab.jobs import convert_video
    from tests.warp.test_video_warp_imports import _clip

    _clip(tmp_path / "clip.mp4")
    _wrapped(monkeypatch, convert_video, "frames_to_files", timers_settled)
    code, out = on_terminal(monkeypatch, ["convert", str(tmp_path / "clip.mp4"), "-o", str(tmp_path / "f_%04d.exr")])
    assert code == 0
    assert "reading" not in out, out
    assert out.endswith("converted 1 of 1 file(s) to EXR\r\n"), out
