"""A lossless RGB clip and its frames as PNG files go through the same decode -> linear -> warp -> encode:
the warped clip and the warped PNGs agree within one 8-bit code value."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio

av = pytest.importorskip("av")

W, H, N = 192, 96, 2


def frames():
    rng = np.random.default_rng(0)
    y, x = np.mgrid[0:H, 0:W]
    out = []
    for k in range(N):  # sharp edges (where a different decoding curve shows most) and noise
        img = np.stack([((x + 3 * k) % 17) * 15, ((y + k) % 9) * 31, rng.integers(0, 256, (H, W))], -1)
        out.append(img.astype(np.uint8))
    return out


def ffv1_rgb_clip(path, codes):
    """What ``ffmpeg -i f%d.png -c:v ffv1 clip.mkv`` makes of PNG frames: packed RGB (bgr0), no transfer tag."""
    with av.open(str(path), "w") as c:
        s = c.add_stream("ffv1", rate=2)
        s.width, s.height, s.pix_fmt = W, H, "bgr0"  # as ffmpeg picks for 8-bit RGB
        for i, img in enumerate(codes):
            f = av.VideoFrame.from_ndarray(img, format="rgb24").reformat(format="bgr0")
            f.pts = i
            for p in s.encode(f):
                c.mux(p)
        for p in s.encode():
            c.mux(p)


def lenslab_cli(*args):
    r = subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


def test_ffv1_clip_and_its_png_frames_warp_alike(tmp_path):
    codes = frames()
    clip = tmp_path / "clip.mkv"
    ffv1_rgb_clip(clip, codes)
    spec = ["--to", "fisheye:fov=180", "--size", "96x96", "--filter", "bicubic", "-q"]
    lenslab_cli("warp", clip, "-o", tmp_path / "w.mkv", *spec)
    with av.open(str(tmp_path / "w.mkv")) as c:
        stream = c.streams.video[0]
        assert stream.codec_context.pix_fmt.startswith("gbrp")  # still RGB, not Y'CbCr tagged as RGB
        got = [f.to_ndarray().astype(np.float64) / 1023 * 255 for f in c.decode(stream)]
    assert len(got) == N
    for k, img in enumerate(codes):
        png = tmp_path / f"f{k}.png"
        lio.write(png, img.astype(np.float32) / 255, raw=True)  # the frame's codes as they are
        lenslab_cli("warp", png, "-o", tmp_path / f"w{k}.png", *spec)
        ref = lio.read(tmp_path / f"w{k}.png", raw=True)[0].astype(np.float64) * 255
        inside = ref[..., 3] == 255  # the image circle (straight colour = colour there)
        assert inside.mean() > 0.7
        # 8-bit PNG rounding (0.5 code) plus the clip's 10-bit rounding (0.125 of an 8-bit code): within 1
        diff = np.abs(got[k] - ref[..., :3])[inside]
        assert diff.max() <= 1.0, diff.max()
