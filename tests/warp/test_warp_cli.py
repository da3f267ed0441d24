"""The 'lenslab warp' command: files in, files out, cameras in headers, alpha, batches."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera
from lenslab.warp import warp


@pytest.fixture
def pano(tmp_path):
    rng = np.random.default_rng(3)
    img = (rng.random((32, 64, 3)) * 8).astype(np.float32)
    path = tmp_path / "pano.exr"
    write(path, img, pixel_type="float")
    return path, img


def test_exr_out_carries_camera_and_alpha(pano, tmp_path):
    path, img = pano
    out = tmp_path / "fish.exr"
    rc = main(["warp", str(path), "-o", str(out), "--to", "fisheye:fov=180", "--size", "24x24", "--yaw", "30",
               "--pixel-type", "float", "-q"])
    assert rc == 0
    got, meta = read(out)
    assert got.shape == (24, 24, 4)
    cam = meta["camera"]
    assert cam.lens.spec() == "fisheye:fov=180,mapping=equidistant" and cam.size == (24, 24)
    assert cam.pose.ypr[0] == pytest.approx(30)
    ref, alpha = warp(img, Camera.from_spec("equirect", (64, 32)), cam)
    np.testing.assert_array_equal(got[..., :3], ref)  # float EXR: bit-exact
    np.testing.assert_array_equal(got[..., 3], alpha)
    assert got[0, 0, 3] == 0 and got[12, 12, 3] == 1  # corner outside the circle, centre inside


def test_warped_exr_can_be_warped_again_from_its_header(pano, tmp_path):
    path, img = pano
    fish = tmp_path / "fish.exr"
    assert main(["warp", str(path), "-o", str(fish), "--to", "fisheye:fov=200", "--size", "48x48",
                 "--pixel-type", "float", "-q"]) == 0
    back = tmp_path / "back.exr"
    # no --from: the fisheye camera comes from fish.exr's header; RGBA in -> premultiplied A out
    assert main(["warp", str(fish), "-o", str(back), "--to", "equirect", "--size", "64x32", "-q",
                 "--pixel-type", "float"]) == 0
    got, meta = read(back)
    assert meta["camera"].lens.name == "equirect"
    a = got[..., 3]
    assert a[16, 32] == 1 and a[16, 0] == 0  # forward seen; straight behind is outside the 200 deg view
    assert np.isfinite(got).all()


def test_png_output_is_tone_mapped_with_alpha(pano, tmp_path):
    path, _ = pano
    out = tmp_path / "view.png"
    assert main(["warp", str(path), "-o", str(out), "--to", "fisheye:fov=180", "--size", "16x16",
                 "--tone", "hable", "-q"]) == 0
    got, meta = read(out)
    assert got.shape == (16, 16, 4) and got.max() <= 1.0
    assert got[0, 0, 3] == 0 and got[8, 8, 3] == 1


def test_source_must_be_known(tmp_path):
    path = tmp_path / "square.exr"
    write(path, np.ones((8, 8, 3), np.float32))
    assert main(["warp", str(path), "-o", str(tmp_path / "o.exr"), "--to", "equirect", "-q"]) == 1
    assert main(["warp", str(path), "-o", str(tmp_path / "o.exr"), "--to", "equirect", "--size", "16x8",
                 "--from", "fisheye:fov=180", "-q"]) == 0


def test_batch_goes_on_after_a_failure_and_reuses_one_map(pano, tmp_path, capsys):
    path, img = pano
    inputs = []
    for k in range(3):
        p = tmp_path / f"frame{k}.exr"
        write(p, img * (k + 1), pixel_type="float")
        inputs.append(str(p))
    bad = tmp_path / "broken.exr"
    bad.write_bytes(b"not an image")
    outdir = tmp_path / "out"
    rc = main(["warp", *inputs, str(bad), "-o", str(outdir), "--to", "perspective:fov=90", "--size", "16x16",
               "--pixel-type", "float"])
    assert rc == 1
    err = capsys.readouterr().err
    assert ": error: " in err and "broken.exr" in err and "warped 3 of 4 file(s) with 1 map(s)" in err
    first = read(outdir / "frame0.exr")[0]
    third = read(outdir / "frame2.exr")[0]
    np.testing.assert_allclose(third[..., :3], 3 * first[..., :3], rtol=1e-6)
    # an existing output is kept without --overwrite
    assert main(["warp", inputs[0], "-o", str(outdir), "--to", "perspective:fov=90", "--size", "16x16", "-q"]) == 1


def test_parallax_needs_permission(pano, tmp_path):
    path, _ = pano
    out = tmp_path / "o.exr"
    args = ["warp", str(path), "-o", str(out), "--to", "perspective", "--size", "8x8", "--eye", "1,0,0", "-q"]
    assert main(args) == 1 and not out.exists()
    assert main(args + ["--allow-parallax"]) == 0 and out.exists()


def test_compat_v360_maps_like_ffmpeg(pano, tmp_path):
    path, img = pano
    out = tmp_path / "half.exr"
    args = ["warp", str(path), "-o", str(out), "--to", "equirect", "--size", "32x16", "--compat", "v360",
            "--pixel-type", "float", "-q"]
    assert main(args) == 0
    # v360 reads index (2i + 1)(W - 1)/W for output pixel i of a 2x reduction (measured from ffmpeg)
    from tests.warp.test_warp_geometry import v360_equirect_resample

    np.testing.assert_allclose(read(out)[0][..., :3], v360_equirect_resample(img, 32, 16), rtol=0, atol=1e-4)
    assert main(args + ["--samples", "4", "--overwrite"]) == 2  # one sample per pixel, as v360: a usage error
