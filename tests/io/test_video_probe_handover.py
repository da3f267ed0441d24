"""A clip admitted by its probe is decoded from the container the probe opened: FFmpeg opens the file once for the
budget's check and the decoding together, and the frames are PyAV's own frames of the file, from the first, as a
fresh open decodes them. A file replaced after its probe is decoded from the new file; a second read opens it anew."""

from __future__ import annotations

import os

import numpy as np
import pytest

av = pytest.importorskip("av")

from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (an H.264 clip whose frames differ, by PyAV)


def _planes_by_pyav(path):
    """Each frame's Y' plane, decoded by PyAV alone (a fresh open)."""
    with av.open(str(path)) as c:
        return [f.to_ndarray()[: f.height].copy() for f in c.decode(video=0)]


@pytest.fixture
def opens(monkeypatch):
    """How many times FFmpeg opens a file (PyAV's ``av.open``)."""
    count = []
    real = av.open
    monkeypatch.setattr(av, "open", lambda *a, **k: count.append(a[0]) or real(*a, **k))
    return count


def _same_as_pyav(clip, index, planes, frames) -> None:
    """The frames read are the clip's ``frames`` frames, each Y' plane PyAV's own of the file, bit for bit."""
    expected = _planes_by_pyav(clip)
    assert index == list(range(frames)) and len(planes) == len(expected) == frames
    for got, want in zip(planes, expected):
        np.testing.assert_array_equal(got, want)


def _read_y(path, window):
    """The frames of read_frames, taken as the warp takes them, and the Y' codes they were converted from."""
    from lenslab.io.video import clips

    seen = []
    real = clips.ycbcr_to_linear
    clips.ycbcr_to_linear = lambda frame, *a, **k: seen.append(frame.to_ndarray()[: frame.height].copy()) or \
        real(frame, *a, **k)
    try:
        frames = [i for i, _ in clips.read_frames(path, prefetch=2, window=window)]
    finally:
        clips.ycbcr_to_linear = real
    return frames, seen


def test_an_admitted_clip_is_opened_once_and_decoded_from_its_first_frame(tmp_path, opens):
    from lenslab.io.budget import admit_clip

    clip = tmp_path / "clip.mp4"
    _clip(clip, frames=5)
    opens.clear()
    admit_clip(clip)
    index, planes = _read_y(clip, lambda: None)
    assert len(opens) == 1
    _same_as_pyav(clip, index, planes, 5)


def test_a_clip_replaced_after_its_probe_is_decoded_from_the_new_file(tmp_path, opens):
    from lenslab.io.video import probe_video

    clip = tmp_path / "clip.mp4"
    _clip(clip, frames=4)
    probe_video(clip)
    other = tmp_path / "other.mp4"
    _clip(other, frames=5)
    os.replace(other, clip)  # same path, another file: another inode
    opens.clear()
    index, planes = _read_y(clip, lambda: None)
    assert len(opens) == 1  # the new file probed, and its container decoded; the old file's was not taken
    _same_as_pyav(clip, index, planes, 5)


def test_a_second_read_of_one_clip_opens_it_again(tmp_path, opens):
    from lenslab.io.video import probe_video

    clip = tmp_path / "clip.mp4"
    _clip(clip, frames=3)
    probe_video(clip)
    first, _ = _read_y(clip, lambda: None)
    opens.clear()
    second, planes = _read_y(clip, lambda: None)
    assert first == [0, 1, 2] and len(opens) == 1
    _same_as_pyav(clip, second, planes, 3)


def test_a_clip_rewritten_in_place_with_its_time_kept_is_decoded_from_what_it_now_holds(tmp_path):
    # rsync -t or cp -p over a clip: the same inode, the same size, the modification time set back; only the
    # status-change time tells the file changed (the kernel sets it on every write and no user can set it back)
    from lenslab.io.video import probe_video

    clip, other = tmp_path / "clip.mkv", tmp_path / "other.mkv"  # FFV1: flat frames 40, 60, ... and 120, 140, ...
    _clip(clip, 64, 32, 4, codec="ffv1", first=40, step=20)
    _clip(other, 64, 32, 4, codec="ffv1", first=120, step=20)
    assert clip.stat().st_size == other.stat().st_size  # (else the size alone would tell them apart)
    probe_video(clip)
    before = clip.stat()
    with open(clip, "r+b") as f:
        f.write(other.read_bytes())
    os.utime(clip, ns=(before.st_atime_ns, before.st_mtime_ns))
    assert (clip.stat().st_ino, clip.stat().st_mtime_ns) == (before.st_ino, before.st_mtime_ns)
    index, planes = _read_y(clip, lambda: None)
    _same_as_pyav(clip, index, planes, 4)
