"""`lenslab warp CLIP -o 'fr/%04d.exr'` writes one image per frame, as `lenslab convert` does: the clip's frame
numbers through printf's %04d (or NAME.000042.exr for a plain image name), each frame read back by OpenImageIO
and checked against the analytic warp of a uniform frame (its linear value inside a 180-degree fisheye's image
circle, nothing outside), the value decoded here by colour-science from the clip's own Y'CbCr planes; all or
none; a name that is neither a clip nor an image is still refused."""

from __future__ import annotations

import subprocess
import sys

import colour
import numpy as np
import pytest

pytest.importorskip("av")
oiio = pytest.importorskip("OpenImageIO")

from tests.io.test_video_size_change import resized  # noqa: E402,F401  (the clip that changes size)
from tests.io.ycbcr_oracle import decode_codes, write_ffv1  # noqa: E402

N, H, W = 4, 16, 32
LEVELS = [0.2, 0.35, 0.5, 0.65]  # one grey per frame: a file's value says which frame it holds


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    path = tmp_path_factory.mktemp("warpclip") / "grey.mkv"
    write_ffv1(path, [np.full((H, W, 3), v) for v in LEVELS])
    # the linear value of each frame: its planes through colour-science's BT.709 decoding, then BT.1886
    linear = [float(colour.models.eotf_BT1886(codes, L_B=0, L_W=1)[H // 2, W // 2, 0]) for codes in decode_codes(path)]
    return path, linear


def _warp(src, out, *extra):
    floats = ["--pixel-type", "float"] if str(out).endswith(".exr") else []  # (a PNG holds no floats: refused)
    return subprocess.run([sys.executable, "-m", "lenslab", "warp", str(src), "--to", "fisheye:fov=180", "--size",
                           "32x32", *floats, "-q", "-o", str(out), *extra], capture_output=True, text=True)


def _oiio(path):
    buf = oiio.ImageBuf(str(path))
    assert not buf.has_error, buf.geterror()
    return buf.get_pixels(oiio.FLOAT), list(buf.spec().channelnames)


def test_a_printf_name_gets_each_frame_numbered_as_in_the_clip(clip, tmp_path):
    src, linear = clip
    out = tmp_path / "fr"
    out.mkdir()
    run = _warp(src, out / "%04d.exr", "--frames", "1:3")
    assert run.returncode == 0, run.stderr
    assert sorted(p.name for p in out.iterdir()) == ["%04d.exr" % i for i in (1, 2)]  # printf's numbering
    for i in (1, 2):
        px, names = _oiio(out / ("%04d.exr" % i))
        assert names == ["R", "G", "B", "A"] and px.shape == (32, 32, 4)
        # a uniform source warps to its own value wherever the view sees it: the centre looks along the
        # axis; float storage and a constant under bilinear weights summing to 1 leave float32 rounding only
        np.testing.assert_allclose(px[16, 16, :3], linear[i], rtol=1e-5)
        assert px[16, 16, 3] == 1.0
        # the corner is at radius sqrt(2) of the image circle's: beyond 90 degrees, outside the fisheye
        assert px[0, 0].tolist() == [0.0, 0.0, 0.0, 0.0]
    assert linear[1] != pytest.approx(linear[2], abs=0.01)  # the frames tell apart


def test_a_plain_image_name_is_numbered_as_convert_numbers_it(clip, tmp_path):
    src, linear = clip
    run = _warp(src, tmp_path / "shot.exr")
    assert run.returncode == 0, run.stderr
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [f"shot.{i:06d}.exr" for i in range(N)]
    for i, name in enumerate(names):
        np.testing.assert_allclose(_oiio(tmp_path / name)[0][16, 16, :3], linear[i], rtol=1e-5)


def test_a_failed_clip_leaves_no_frame(resized, tmp_path):  # noqa: F811
    clip_path, _, _, n = resized
    assert n == 6  # PyAV decodes six frames of the first size before the failure
    out = tmp_path / "fr"
    out.mkdir()
    run = _warp(clip_path, out / "f_%04d.png")
    assert run.returncode == 1
    assert f"frame {n} " in run.stderr
    assert list(out.iterdir()) == []  # neither the six frames nor a temporary


def test_a_name_neither_clip_nor_image_is_refused(clip, tmp_path):
    src, _ = clip
    run = _warp(src, tmp_path / "out.xyz")
    assert run.returncode == 1
    assert f"{src} is a video: give -o NAME with one of .mp4" in run.stderr
    assert list(tmp_path.iterdir()) == []
