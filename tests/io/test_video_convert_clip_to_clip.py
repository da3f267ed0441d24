"""convert: a clip given to a clip output is re-encoded whole (every frame, or those of --frames, at the input's
own rate), not cut to its first frame. The clips are made here with PyAV and decoded with PyAV and
colour-science (:mod:`tests.io.ycbcr_oracle`), so the frame counts, rates and pixels come from outside lenslab."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.cli.main import main  # noqa: E402
from tests.io.ycbcr_oracle import decode_codes, write_ffv1  # noqa: E402

W, H, N = 32, 16, 4


def _frames():
    y, x = np.mgrid[0:H, 0:W]
    return [np.stack([x / W, y / H, np.full((H, W), (i + 1) / (N + 1))], -1) * 0.9 + 0.05 for i in range(N)]


def _decoded(path):
    """Linear frames (BT.709 limited-range Y'CbCr decoded by colour-science, then BT.1886) and the stream's rate."""
    frames = [colour.models.eotf_BT1886(codes, L_B=0, L_W=1) for codes in decode_codes(path)]
    with av.open(str(path)) as c:
        return frames, Fraction(c.streams.video[0].average_rate)


@pytest.mark.slow
def test_a_clip_to_a_clip_keeps_every_frame_and_its_rate(tmp_path):
    write_ffv1(tmp_path / "in.mkv", _frames())  # 25 frames/s (PyAV)
    want, rate_in = _decoded(tmp_path / "in.mkv")
    assert len(want) == N and rate_in == 25
    assert main(["convert", str(tmp_path / "in.mkv"), "-o", str(tmp_path / "out.mkv"), "-q"]) == 0
    got, rate = _decoded(tmp_path / "out.mkv")
    assert len(got) == N  # (it was 1: the first frame only)
    assert rate == rate_in  # the input clip's rate, not the default 24 of a clip made from images
    for g, w in zip(got, want):
        # two 10-bit limited-range Y'CbCr encodings: a step is 1/876 of the range, times the gamma-2.4 slope
        # (<= 2.4), once each way
        np.testing.assert_allclose(g, w, atol=0.012)


@pytest.mark.slow
def test_frames_pick_the_clips_frames_and_a_still_adds_one(tmp_path):
    write_ffv1(tmp_path / "in.mkv", _frames())
    want, _ = _decoded(tmp_path / "in.mkv")
    assert main(["convert", str(tmp_path / "in.mkv"), "-o", str(tmp_path / "part.mkv"), "--frames", "1:3",
                 "-q"]) == 0
    got, _ = _decoded(tmp_path / "part.mkv")
    assert len(got) == 2
    for g, w in zip(got, want[1:3]):
        np.testing.assert_allclose(g, w, atol=0.012)
    # a still image then the clip: 1 + N frames, in the order given, at the clip's rate (--rate not given)
    still = tmp_path / "still.pfm"
    still.write_bytes(b"PF\n%d %d\n-1.0\n" % (W, H) + np.full((H, W, 3), 0.5, "<f4").tobytes())
    assert main(["convert", str(still), str(tmp_path / "in.mkv"), "-o", str(tmp_path / "both.mkv"),
                 "--tone", "clamp", "-q"]) == 0
    got, rate = _decoded(tmp_path / "both.mkv")
    assert len(got) == 1 + N and rate == 25
    np.testing.assert_allclose(got[0], 0.5, atol=0.012)
    np.testing.assert_allclose(got[-1], want[-1], atol=0.012)
