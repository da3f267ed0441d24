"""Video: clips made here with PyAV, warped by `lenslab warp`, compared frame by frame with warping the frames
decoded independently (PyAV + colour-science's transfer functions); count, rate, colour tags and audio kept."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.cli.main import main  # noqa: E402
from lenslab.lenses import Camera  # noqa: E402
from lenslab.warp import warp  # noqa: E402
from tests.io.ycbcr_oracle import exact_codes  # noqa: E402

W, H, N = 64, 32, 4
TO = "fisheye:fov=180"


def _pattern(i, bits):
    """A smooth frame (codes in [0.05, 0.95]) that moves with i."""
    y, x = np.mgrid[0:H, 0:W]
    v = np.stack([0.5 + 0.45 * np.sin(x / 7.0 + i), 0.5 + 0.45 * np.cos(y / 5.0 - i), (x + y + 8 * i) % 64 / 70 + 0.05],
                 -1)
    return np.round(v * (2**16 - 1)).astype(np.uint16)


def _make(path, encoder, pix_fmt, trc, primaries, matrix, rate=Fraction(25), audio=False):
    with av.open(str(path), "w") as c:
        s = c.add_stream(encoder, rate=rate)
        s.width, s.height, s.pix_fmt = W, H, pix_fmt
        cc = s.codec_context
        cc.color_trc, cc.color_primaries, cc.colorspace, cc.color_range = trc, primaries, matrix, 1
        if encoder == "libx265":
            cc.options = {"x265-params": "log-level=error"}
        a = c.add_stream("aac", rate=48000) if audio else None
        for i in range(N):
            f = av.VideoFrame.from_ndarray(_pattern(i, 16), format="rgb48le")
            f = f.reformat(format=pix_fmt, dst_colorspace="bt2020" if matrix == 9 else "itu709",
                           src_color_range="JPEG", dst_color_range="MPEG")
            f.pts = i
            for p in s.encode(f):
                c.mux(p)
        for p in s.encode():
            c.mux(p)
        if a is not None:
            af = av.AudioFrame.from_ndarray(np.zeros((1, 4096), np.float32), format="fltp", layout="mono")
            af.sample_rate, af.pts = 48000, 0
            for p in list(a.encode(af)) + list(a.encode()):
                c.mux(p)


def _decode(path):
    """Frames as linear Rec.709, decoded here: colour-science's Y'CbCr decoding with the stream's matrix and range
    (:mod:`tests.io.ycbcr_oracle`; swscale is 0.4 % low at white), then its EOTF."""
    with av.open(str(path)) as c:
        s = c.streams.video[0]
        cc = s.codec_context
        tags = (int(cc.color_primaries), int(cc.color_trc), int(cc.colorspace), int(cc.color_range))
        frames = []
        for f in c.decode(s):
            rgb = exact_codes(f, tags[2], tags[3] == 2)
            if tags[1] == 16:  # PQ, 1.0 = 203 cd/m2 (BT.2408), BT.2020 primaries to Rec.709
                lin = colour.models.eotf_ST2084(rgb) / 203.0
                m = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"],
                                             colour.RGB_COLOURSPACES["ITU-R BT.709"])
                lin = lin @ m.T
            else:  # BT.709 video: the BT.1886 display EOTF
                lin = colour.models.eotf_BT1886(rgb, L_B=0, L_W=1)
            frames.append(lin.astype(np.float32))
        return frames, Fraction(s.average_rate), tags, cc.pix_fmt, len(c.streams.audio)


def _expected(frames):
    src = Camera.from_spec("equirect", (W, H))
    dst = Camera.from_spec(TO, (32, 32))
    return [warp(f, src, dst)[0] for f in frames]


@pytest.mark.slow
def test_sdr_clip_warped_frame_by_frame(tmp_path):
    _make(tmp_path / "in.mp4", "libx264", "yuv420p", 1, 1, 1, rate=Fraction(30000, 1001), audio=True)
    assert main(["warp", str(tmp_path / "in.mp4"), "-o", str(tmp_path / "out.mkv"), "--to", TO, "--size", "32x32",
                 "-q"]) == 0
    src, rate_in, tags_in, _, _ = _decode(tmp_path / "in.mp4")
    out, rate, tags, pix_fmt, audio = _decode(tmp_path / "out.mkv")
    assert len(out) == N and rate == Fraction(30000, 1001) and tags == tags_in == (1, 1, 1, 1)
    assert pix_fmt == "yuv444p10le" and audio == 1  # FFV1 10-bit by the .mkv default; the audio stream copied
    for got, want in zip(out, _expected(src)):
        # FFV1 is lossless: what differs is the 10-bit limited-range YUV quantisation (1/876 of the code
        # range per step, through the matrix and a gamma-2.4 slope of at most 2.4): 0.01 in linear light
        np.testing.assert_allclose(got, want, atol=0.01)


@pytest.mark.slow
def test_pq_clip_stays_pq_bt2020(tmp_path):
    _make(tmp_path / "hdr.mkv", "ffv1", "yuv444p10le", 16, 9, 9)
    assert main(["warp", str(tmp_path / "hdr.mkv"), "-o", str(tmp_path / "out.mkv"), "--to", TO, "--size", "32x32",
                 "--frames", "1:3", "-q"]) == 0
    src, _, tags_in, _, _ = _decode(tmp_path / "hdr.mkv")
    out, rate, tags, pix_fmt, _ = _decode(tmp_path / "out.mkv")
    assert len(out) == 2 and rate == 25 and tags == tags_in == (9, 16, 9, 1) and pix_fmt == "yuv444p10le"
    for got, want in zip(out, _expected(src[1:3])):
        # PQ is steep: one 10-bit step near the top of these codes (0.95) is about 1.5 % of the value, and
        # the BT.2020 -> Rec.709 matrix spreads each component's error over the pixel: bound by its largest
        scale = np.abs(want).max(axis=-1, keepdims=True)
        assert (np.abs(got - want) <= 0.03 * scale + 1e-3).all()


def test_h265_needs_ten_bits_and_frames_are_checked(tmp_path):
    _make(tmp_path / "hdr.mkv", "ffv1", "yuv444p10le", 16, 9, 9)
    assert main(["warp", str(tmp_path / "hdr.mkv"), "-o", str(tmp_path / "o.mp4"), "--to", TO, "--size", "32x32",
                 "--codec", "h264", "-q"]) == 1  # PQ in 8-bit H.264 is refused
    assert not (tmp_path / "o.mp4").exists()  # and nothing half-written is left
    with pytest.raises(SystemExit) as exc:  # an empty range: a usage error before anything is read
        main(["warp", str(tmp_path / "hdr.mkv"), "-o", str(tmp_path / "o.mkv"), "--to", TO, "--frames", "5:2", "-q"])
    assert exc.value.code == 2


@pytest.mark.slow
def test_display_transform_to_pq_video(tmp_path):
    ocio = pytest.importorskip("PyOpenColorIO")
    _make(tmp_path / "in.mkv", "ffv1", "yuv444p10le", 1, 1, 1)
    view = "ACES 2.0 - HDR 1000 nits (Rec.2020)"
    assert main(["warp", str(tmp_path / "in.mkv"), "-o", str(tmp_path / "pq.mkv"), "--to", TO, "--size", "32x32",
                 "--display", "Rec.2100-PQ - Display", "--view", view, "-q"]) == 0
    src, _, _, _, _ = _decode(tmp_path / "in.mkv")
    with av.open(str(tmp_path / "pq.mkv")) as c:
        cc = c.streams.video[0].codec_context
        assert (int(cc.color_primaries), int(cc.color_trc), int(cc.colorspace)) == (9, 16, 9)  # BT.2020 PQ tags
        codes = [exact_codes(f, 9, False) for f in c.decode(c.streams.video[0])]
    cfg = ocio.Config.CreateFromFile("ocio://default")
    cpu = cfg.getProcessor("Linear Rec.709 (sRGB)", "Rec.2100-PQ - Display", view,
                           ocio.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    for got, warped in zip(codes, _expected(src)):
        want = np.ascontiguousarray(warped, np.float32).copy()
        cpu.applyRGB(want)
        # PQ code values through 10-bit limited-range YUV 4:4:4: a step is 1/876, two through the matrix
        np.testing.assert_allclose(got, np.clip(want, 0, 1), atol=3 / 876)
