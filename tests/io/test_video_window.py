"""Frames decoded only in a window (the pixels a warp reads: the compiled Y'CbCr pass reads only their samples,
into one buffer reused frame to frame) hold in that window the values the whole frame's decoding gives, frame after
frame, and 0 outside it."""

from __future__ import annotations

import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.io.video import read_frames  # noqa: E402
from tests.io.ycbcr_oracle import write_ffv1  # noqa: E402

W, H, N = 64, 32, 11  # frames enough that a stale buffer or a frame converted out of turn would show


def _make(path, pix_fmt):
    y, x = np.mgrid[0:H, 0:W]
    write_ffv1(path, [np.stack([(x + 5 * i) % W / W, y / H, np.full((H, W), i / N)], -1) * 0.9 + 0.05
                      for i in range(N)], pix_fmt)


@pytest.mark.parametrize("pix_fmt", ["yuv420p", "yuv420p10le", "yuv422p10le", "yuv444p10le"])
def test_windowed_frames_equal_whole_frames_in_the_window(tmp_path, pix_fmt):
    _make(tmp_path / "clip.mkv", pix_fmt)
    box = (3, 29, 10, 41)  # the crop around it: columns 0 to 52 of 64
    whole = [f for _, f in read_frames(tmp_path / "clip.mkv")]
    parts, buffers = [], set()
    for _, f in read_frames(tmp_path / "clip.mkv", window=lambda: box):
        buffers.add(f.__array_interface__["data"][0])
        parts.append(f.copy())  # valid until the next frame is taken
    assert len(parts) == len(whole) == N and len(buffers) == 1  # one buffer, converted as each frame is taken
    r0, r1, c0, c1 = box
    for part, want in zip(parts, whole):
        np.testing.assert_array_equal(part[r0:r1, c0:c1], want[r0:r1, c0:c1])
        part[r0:r1, c0:c1] = 0
        assert not part.any()
    assert len({w.tobytes() for w in whole}) == N  # the frames differ: a stale buffer would show
