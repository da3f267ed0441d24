"""A clip written to `-o 'ff/%04d.png'` gets its folder made as `-o DIR` is (parents too), once every check has
passed, for convert and warp alike; a command that fails having written nothing there leaves no folder. The
frames are read back by OpenCV and checked against the clip decoded here by colour-science: its planes through
BT.709's Y'CbCr decoding and BT.1886's EOTF to linear light, then the sRGB encoding of a PNG."""

from __future__ import annotations

import subprocess
import sys

import colour
import numpy as np
import pytest

pytest.importorskip("av")
cv2 = pytest.importorskip("cv2")

from tests.io.test_video_size_change import resized  # noqa: E402,F401  (the clip that changes size)
from tests.io.test_video_warp_frames import N, clip  # noqa: E402,F401  (four grey frames)
from tests.io.ycbcr_oracle import decode_codes  # noqa: E402


def _srgb_codes(src):
    """Each frame of ``src`` as 8-bit sRGB codes (float64, unrounded), by colour-science alone."""
    return [colour.models.eotf_inverse_sRGB(colour.models.eotf_BT1886(c, L_B=0, L_W=1)) * 255
            for c in decode_codes(src)]


def _lenslab(*argv):
    return subprocess.run([sys.executable, "-m", "lenslab", *map(str, argv), "-q"], capture_output=True, text=True)


def test_convert_makes_the_pattern_folder(clip, tmp_path):  # noqa: F811
    src, _ = clip
    run = _lenslab("convert", src, "--to", "png", "-o", tmp_path / "ff" / "%04d.png")
    assert run.returncode == 0, run.stderr
    names = sorted(p.name for p in (tmp_path / "ff").iterdir())
    assert names == ["%04d.png" % i for i in range(N)]
    for want, name in zip(_srgb_codes(src), names):
        png = cv2.imread(str(tmp_path / "ff" / name), cv2.IMREAD_UNCHANGED)
        # 8-bit codes: one code of rounding
        np.testing.assert_allclose(png[..., ::-1].astype(float), want, atol=1.0)


def test_warp_makes_the_pattern_folder_and_its_parents(clip, tmp_path):  # noqa: F811
    src, _ = clip
    out = tmp_path / "ff" / "fish" / "%04d.png"
    run = _lenslab("warp", src, "--to", "fisheye:fov=180", "--size", "32x32", "--frames", "2:4", "-o", out)
    assert run.returncode == 0, run.stderr
    assert sorted(p.name for p in out.parent.iterdir()) == ["0002.png", "0003.png"]
    codes = _srgb_codes(src)
    for i in (2, 3):
        png = cv2.imread(str(out.parent / ("%04d.png" % i)), cv2.IMREAD_UNCHANGED)
        assert png.shape == (32, 32, 4)  # RGBA: alpha 0 outside the image circle
        # the centre sees the uniform frame: its value, developed as a still image to PNG is (one code of rounding)
        np.testing.assert_allclose(png[16, 16, 2::-1].astype(float), codes[i][8, 16], atol=1.0)
        assert png[16, 16, 3] == 255 and png[0, 0, 3] == 0  # the corner is beyond 90 degrees


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["warp", "--to", "fisheye:fov=180", "--size", "32x32"]])
def test_a_failed_clip_leaves_no_folder(resized, tmp_path, command):  # noqa: F811
    clip_path, _, _, n = resized
    run = _lenslab(command[0], clip_path, *command[1:], "-o", tmp_path / "gone" / "deeper" / "%04d.png")
    assert run.returncode == 1
    assert f"frame {n} " in run.stderr  # failed at the frame of another size, having written nothing
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["warp", "--to", "fisheye:fov=180", "--size", "32x32"]])
def test_no_frame_in_the_range_leaves_no_folder(clip, tmp_path, command):  # noqa: F811
    src, _ = clip
    run = _lenslab(command[0], src, *command[1:], "--frames", f"{N + 3}:{N + 5}", "-o", tmp_path / "gone" / "%04d.png")
    assert run.returncode == 1
    assert "no frame in the range" in run.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_usage_error_makes_no_folder(clip, tmp_path):  # noqa: F811
    src, _ = clip
    run = _lenslab("warp", src, "--to", "fisheye:fov=180", "--tone", "clamp", "-o", tmp_path / "ff" / "%04d.exr")
    assert run.returncode == 2  # --tone with an output that keeps linear light
    assert list(tmp_path.iterdir()) == []


def test_a_folder_already_there_is_kept_when_the_command_fails(resized, tmp_path):  # noqa: F811
    clip_path, _, _, _ = resized
    (tmp_path / "ff").mkdir()
    run = _lenslab("convert", clip_path, "--to", "png", "-o", tmp_path / "ff" / "%04d.png")
    assert run.returncode == 1
    assert (tmp_path / "ff").is_dir() and list((tmp_path / "ff").iterdir()) == []


def test_a_still_image_to_a_missing_folder_is_still_refused(tmp_path):
    import lenslab.io as lio

    lio.write(tmp_path / "still.exr", np.ones((8, 16, 3), np.float32))
    run = _lenslab("convert", tmp_path / "still.exr", "--to", "png", "-o", tmp_path / "ff" / "%04d.png")
    assert run.returncode == 1
    assert "the folder" in run.stderr and "does not exist" in run.stderr  # one image: no sequence, no folder made
    assert not (tmp_path / "ff").exists()
