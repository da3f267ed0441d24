"""``lenslab warp --flip`` writes the view its pixels show, and records that view: a mirrored camera (a turn after a
reflection of the lens's rays, ``mirror = "h"`` beside yaw, pitch and roll), so that ``--to`` the output, ``lenslab
info`` and every reader of the recorded camera see what the pixels hold.

Outside values: the pixels of ``--flip h --yaw 30`` are those of the unmirrored ``--yaw -30`` view read right to left
(NumPy's ``[:, ::-1]``: mirroring the world's x turns a yaw of 30 into -30), and the recorded camera's ray for each
pixel centre equals the perspective formula of ``docs/conventions.md`` written out here in float64, mirrored and
turned."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write

W, H, FOV = 64, 48, 60.0


def _source(path, camera=None):
    """A 256 x 128 equirect of smooth colour with detail (no two columns alike), float32 in an EXR."""
    y, x = np.mgrid[0:128, 0:256].astype(np.float64)
    img = np.stack([1.5 + np.sin(x / 9.0), 1.5 + np.cos(y / 7.0), 0.2 + (x + 3 * y) / 640.0], axis=-1)
    write(path, img.astype(np.float32), pixel_type="float", camera=camera)
    return path


def _warp(src, out, *flags):
    assert main(["warp", str(src), "-o", str(out), "--size", f"{W}x{H}", "--pixel-type", "float", "-q",
                 *flags]) == 0
    return read(out)


def _ry(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rx(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _perspective_rays():
    """Unit camera rays of a perspective lens of horizontal ``FOV`` at every pixel centre, float64 (H, W, 3):
    ``d ~ (u tan(fov/2), v tan(fov/2), 1)``, ``u = 2x/W - 1``, ``v = (1 - 2y/H) H/W`` (square pixels)."""
    y, x = np.mgrid[0:H, 0:W].astype(np.float64) + 0.5
    t = np.tan(np.radians(FOV) / 2)
    d = np.stack([(2 * x / W - 1) * t, (1 - 2 * y / H) * (H / W) * t, np.ones_like(x)], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _flop_of_yaw_30():
    """The world rays of ``--yaw 30 --flip h`` from an unturned source: ``M_h Ry(30) d``, written out."""
    d = _perspective_rays()
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    return np.stack([-(c * d[..., 0] + s * d[..., 2]), d[..., 1], -s * d[..., 0] + c * d[..., 2]], axis=-1)


def _recorded_rays(meta):
    y, x = np.mgrid[0:H, 0:W].astype(np.float64) + 0.5
    cam = meta["camera"]
    _, dirs, valid = cam.pixel_to_world(np.stack([x, y], axis=-1).reshape(-1, 2))
    assert valid.all()
    return dirs.reshape(H, W, 3)


#: the warp's float32 rounding: maps and samples are float32, values near 2.5, so a few units in the last place of
#: 2.5 (2.4e-7 each) between two warps that reach a pixel by different float64 sums
F32 = 8 * np.spacing(np.float32(2.5))


def test_a_left_right_flip_is_the_mirrored_view_and_records_it(tmp_path):
    src = _source(tmp_path / "src.exr")
    flipped, meta = _warp(src, tmp_path / "flipped.exr", "--to", f"perspective:fov={FOV:g}", "--yaw", "30",
                          "--flip", "h")
    plain, _ = _warp(src, tmp_path / "plain.exr", "--to", f"perspective:fov={FOV:g}", "--yaw", "-30")
    np.testing.assert_allclose(flipped[..., :3], plain[:, ::-1, :3], rtol=0, atol=F32)
    # the recorded camera sends each pixel's ray where the pixel looked: M_h Ry(30) d, i.e. Ry(-30) M_h d
    want = _flop_of_yaw_30()
    np.testing.assert_allclose(_recorded_rays(meta), want, rtol=0, atol=1e-12)  # float64 rounding of a few products
    assert meta["camera"].pose.mirror == "h"
    # warped again to the file's view, the same source gives the file's pixels
    again, _ = _warp(src, tmp_path / "again.exr", "--to", str(tmp_path / "flipped.exr"))
    np.testing.assert_allclose(again, flipped, rtol=0, atol=F32)


@pytest.mark.parametrize("flips", ["h", "v", "d", "hv", "hvd"])
def test_a_flip_of_a_source_that_records_its_pose_is_recorded_in_the_sources_world(tmp_path, flips):
    """The mirror is of the source camera's axes (v360's flips): a pixel's ray is ``R_s M R_s^T R_dst d`` in the
    world of a source turned by ``R_s``; the file records exactly that, and ``--to`` it warps the same pixels."""
    from lenslab.lenses import Camera

    src = _source(tmp_path / "src.exr", Camera.from_spec("equirect", (256, 128), yaw=50, pitch=20))
    flipped, meta = _warp(src, tmp_path / "flipped.exr", "--to", f"perspective:fov={FOV:g}", "--yaw", "30",
                          "--pitch", "-10", "--flip", flips)
    r_s = _ry(50) @ _rx(-20)
    m = np.diag([-1.0 if c in flips else 1.0 for c in "hvd"])
    want = _perspective_rays() @ (r_s @ m @ r_s.T @ _ry(30) @ _rx(10)).T
    np.testing.assert_allclose(_recorded_rays(meta), want, rtol=0, atol=1e-12)
    assert (meta["camera"].pose.mirror == "") == (np.linalg.det(m) > 0)  # h and v together: a half turn, no mirror
    again, _ = _warp(src, tmp_path / "again.exr", "--to", str(tmp_path / "flipped.exr"))
    np.testing.assert_allclose(again, flipped, rtol=0, atol=F32)


def test_info_says_the_view_is_mirrored(tmp_path, capsys):
    src = _source(tmp_path / "src.exr")
    _warp(src, tmp_path / "flipped.exr", "--to", f"perspective:fov={FOV:g}", "--yaw", "30", "--flip", "h")
    capsys.readouterr()
    assert main(["info", str(tmp_path / "flipped.exr")]) == 0
    out = capsys.readouterr().out
    assert "pose: mirrored left-right (h), then yaw -30, pitch 0, roll 0 degrees; eye (0, 0, 0)" in out, out


def test_a_clips_frames_record_the_mirrored_view(tmp_path):
    av = pytest.importorskip("av")
    from tests.warp.test_video_warp_imports import _clip

    assert av
    clip = tmp_path / "clip.mp4"
    _clip(clip, w=128, h=64, frames=2)
    assert main(["warp", str(clip), "-o", str(tmp_path / "f_%04d.exr"), "--from", "equirect", "--to",
                 f"perspective:fov={FOV:g}", "--yaw", "30", "--flip", "h", "--size", f"{W}x{H}", "-q"]) == 0
    want = _flop_of_yaw_30()
    frames = sorted(tmp_path.glob("f_*.exr"))
    assert len(frames) == 2
    for f in frames:
        np.testing.assert_allclose(_recorded_rays(read(f)[1]), want, rtol=0, atol=1e-12)


def test_a_camera_file_gives_its_mirror_in_words():
    """``mirror = "h"`` beside yaw: the lens's x reflected, then turned (``Ry(yaw) diag(-1, 1, 1)``); a mirror of
    other letters is refused in one line."""
    from lenslab.errors import LensError
    from lenslab.lenses import Camera

    cam = Camera.from_toml('yaw = -30.0\nmirror = "h"\n[lens]\nmodel = "perspective"\nsize = [64, 48]\nfov = 60.0\n')
    np.testing.assert_allclose(cam.pose.rotation, _ry(-30) @ np.diag([-1.0, 1.0, 1.0]), rtol=0, atol=1e-15)
    assert Camera.from_toml(cam.to_toml()).pose.rotation.tolist() == cam.pose.rotation.tolist()
    with pytest.raises(LensError, match="mirror must be letters among h"):
        Camera.from_toml('mirror = "x"\n[lens]\nmodel = "perspective"\nsize = [64, 48]\n')


def test_a_flop_warped_back_to_the_panorama_lands_on_the_source(tmp_path):
    """The recorded camera read as a source: the flop of ``--yaw 30 --flip h`` warped back to an equirect puts each
    pixel where the source panorama holds it (centred on yaw -30). Tolerance 0.01: two bilinear resamplings of a
    sinusoid of 40-pixel period (measured 0.0025); another view there (the unmirrored yaw 30) is off by up to 2."""
    y, x = np.mgrid[0:256, 0:512].astype(np.float64)
    pano = np.stack([1.5 + np.sin(x / 40.0), 1.5 + np.cos(y / 30.0), 0.2 + (x + 3 * y) / 2000], axis=-1)
    write(tmp_path / "pano.exr", pano.astype(np.float32), pixel_type="float")
    assert main(["warp", str(tmp_path / "pano.exr"), "-o", str(tmp_path / "flop.exr"), "--to", "perspective:fov=60",
                 "--yaw", "30", "--flip", "h", "--size", "400x300", "--pixel-type", "float", "-q"]) == 0
    assert main(["warp", str(tmp_path / "flop.exr"), "-o", str(tmp_path / "back.exr"), "--to", "equirect", "--size",
                 "512x256", "--pixel-type", "float", "-q"]) == 0
    back = read(tmp_path / "back.exr")[0]
    seen = back[..., 3] > 0.999
    cols = np.where(seen.any(axis=0))[0]
    assert abs((cols.min() + cols.max() + 1) / 2 - 512 * (0.5 - 30 / 360)) < 2  # centred on yaw -30
    np.testing.assert_allclose(back[..., :3][seen], pano[seen], rtol=0, atol=0.01)
