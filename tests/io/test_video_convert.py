"""convert: a clip made here with PyAV to one EXR per frame (checked against PyAV + colour-science's BT.1886
decoding done here, exact to BT.709), and EXR frames back to a clip (rate, size, tags and pixels checked the same way)."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402
from tests.io.ycbcr_oracle import decode_codes, write_ffv1  # noqa: E402

W, H, N = 64, 32, 3


def _make(path):
    y, x = np.mgrid[0:H, 0:W]
    write_ffv1(path, [np.stack([x / W, y / H, np.full((H, W), (i + 1) / 4)], -1) * 0.9 + 0.05 for i in range(N)])


def _decode(path):
    """Linear frames decoded here: the planes through colour-science's BT.709 limited-range Y'CbCr decoding
    (:mod:`tests.io.ycbcr_oracle`; swscale is 0.4 % low at white), then its BT.1886 EOTF."""
    frames = [colour.models.eotf_BT1886(codes, L_B=0, L_W=1) for codes in decode_codes(path)]
    with av.open(str(path)) as c:
        s = c.streams.video[0]
        cc = s.codec_context
        return frames, Fraction(s.average_rate), (int(cc.color_primaries), int(cc.color_trc), int(cc.colorspace))


@pytest.mark.slow
def test_clip_to_exr_frames_and_back(tmp_path):
    _make(tmp_path / "clip.mkv")
    want, _, _ = _decode(tmp_path / "clip.mkv")
    assert main(["convert", str(tmp_path / "clip.mkv"), "--to", "exr", "-o", str(tmp_path / "frames"),
                 "--pixel-type", "float", "-q"]) == 0
    files = sorted((tmp_path / "frames").iterdir())
    assert [p.name for p in files] == [f"clip.{i:06d}.exr" for i in range(N)]
    for p, w in zip(files, want):
        np.testing.assert_allclose(lio.read(p)[0], w, atol=1e-6)  # the same decoding, float32 storage
    assert main(["convert", str(tmp_path / "clip.mkv"), "--to", "exr", "-o", str(tmp_path / "part"),
                 "--frames", "1:2", "-q"]) == 0
    assert [p.name for p in (tmp_path / "part").iterdir()] == ["clip.000001.exr"]
    # and back: the frames as one FFV1 clip at 29.97 fps, values kept by the clamp curve (all below 1)
    assert main(["convert", *map(str, files), "--to", "mkv", "-o", str(tmp_path / "back.mkv"), "--rate", "29.97",
                 "--tone", "clamp", "-q"]) == 0
    back, rate, tags = _decode(tmp_path / "back.mkv")
    assert len(back) == N and rate == Fraction(2997, 100) and tags == (1, 1, 1)
    for got, w in zip(back, want):
        # 10-bit limited-range YUV once more: a step is 1/876 of the range, times the gamma-2.4 slope (<= 2.4)
        np.testing.assert_allclose(got, w, atol=0.006)
