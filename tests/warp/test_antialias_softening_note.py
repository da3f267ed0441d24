"""--antialias on a view that shrinks the source nowhere softens it, as its model says, and the command says so.

The footprint filter is the box average of the bilinear source over each output pixel. Over a pixel that covers
exactly one source pixel (an identity warp) the 1-D hat function integrates over [-1/2, 1/2] to 3/4 for the texel
under it and 1/8 for each neighbour, so the 2-D weights are 9/16 (centre), 3/32 (sides) and 1/64 (corners): the
test convolves a random panorama with that kernel in float64 and compares. Such a warp gets one note; the bench's
minifying fisheye (a 4:1 equirect into a 180-degree fisheye) gets none. Which footprints shrink the source is
checked against LAPACK's singular values (numpy.linalg.svd)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera
from lenslab.warp import WarpPlan
from lenslab.warp.minification import NOTE, SHRINK, band_shrinks, shrinks

W, H = 96, 48


def _blurred(img: np.ndarray) -> np.ndarray:
    """The box average of the bilinear reconstruction over each 1x1 pixel centred on a texel, float64: weights
    9/16, 3/32 (four sides), 1/64 (four corners); columns wrap around the panorama's seam."""
    x = img.astype(np.float64)
    kernel = np.array([[1 / 64, 3 / 32, 1 / 64], [3 / 32, 9 / 16, 3 / 32], [1 / 64, 3 / 32, 1 / 64]])
    assert kernel.sum() == 1.0
    out = np.zeros_like(x)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            out += kernel[dy + 1, dx + 1] * np.roll(np.roll(x, -dy, axis=0), -dx, axis=1)
    return out


@pytest.fixture
def forest(tmp_path):
    img = np.random.default_rng(11).random((H, W, 3)).astype(np.float32) * 4
    path = tmp_path / "forest.exr"
    write(path, img, pixel_type="float")
    return path, img


def test_an_identity_warp_with_antialias_blurs_by_the_model_and_says_so(forest, tmp_path, capsys):
    path, img = forest
    out = tmp_path / "out.exr"
    rc = main(["warp", str(path), "-o", str(out), "--to", "equirect", "--antialias", "--pixel-type", "float"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert err.count("note:") == 1 and f"lenslab warp: note: {path}: {NOTE}" in err
    got, _ = read(out)
    want = _blurred(img)
    inner = slice(1, H - 1)  # off the pole rows, whose neighbours across the pole are other texels than a roll's
    # the filter integrates in float64 and rounds once to the float32 output: within 2 float32 ulps (1.2e-7 each)
    np.testing.assert_allclose(got[inner, :, :3], want[inner], rtol=2.4e-7, atol=0)
    # and it is a blur, not the input: the mean relative difference the user saw is this kernel's
    assert np.mean(np.abs(got[inner, :, :3] - img[inner]) / img[inner]) > 0.05


def test_a_batch_of_identity_warps_gets_the_note_once(forest, tmp_path, capsys):
    path, img = forest
    other = tmp_path / "lake.exr"
    write(other, img[::-1].copy(), pixel_type="float")
    rc = main(["warp", str(path), str(other), "-o", str(tmp_path / "soft"), "--to", "equirect", "--antialias",
               "--jobs", "2"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert err.count(NOTE) == 1


@pytest.mark.parametrize("out", ["same.mp4", "frames/%02d.exr"])
def test_a_clip_warped_in_place_gets_the_note_once(tmp_path, capsys, out):
    av = pytest.importorskip("av")
    clip = tmp_path / "clip.mp4"
    with av.open(str(clip), "w") as c:
        s = c.add_stream("mpeg4", rate=25)
        s.width, s.height, s.pix_fmt = W, H, "yuv420p"
        rng = np.random.default_rng(4)
        for i in range(3):
            f = av.VideoFrame.from_ndarray(rng.integers(0, 256, (H, W, 3), dtype=np.uint8), format="rgb24")
            f.pts = i
            for p in s.encode(f.reformat(format="yuv420p")):
                c.mux(p)
        for p in s.encode():
            c.mux(p)
    rc = main(["warp", str(clip), "-o", str(tmp_path / out), "--to", "equirect", "--antialias"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert err.count(NOTE) == 1


def test_the_benchs_minifying_fisheye_gets_no_note(tmp_path, capsys):
    # the bench's accuracy geometry: a 1024x512 panorama into a 256x256 180-degree fisheye
    img = np.random.default_rng(2).random((512, 1024, 3)).astype(np.float32)
    path = tmp_path / "forest.exr"
    write(path, img, pixel_type="float")
    rc = main(["warp", str(path), "-o", str(tmp_path / "fish.exr"), "--to", "fisheye:fov=180", "--size", "256x256",
               "--antialias"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "note:" not in err
    plan = WarpPlan(Camera.from_spec("equirect", (1024, 512)), Camera.from_spec("fisheye:fov=180", (256, 256)),
                    antialias=True)
    assert shrinks(plan) is None  # nothing drawn yet
    plan.run(img)
    assert shrinks(plan) is True


def test_an_enlarging_view_shrinks_nowhere():
    # a 60-degree view of a 96x48 panorama at 256x256: each output pixel covers about 1/15 of a source pixel
    plan = WarpPlan(Camera.from_spec("equirect", (W, H)), Camera.from_spec("perspective:fov=60", (256, 256)),
                    antialias=True)
    plan.run(np.ones((H, W, 3), np.float32))
    assert shrinks(plan) is False


_sides = arrays(np.float32, (64, 4), elements=st.floats(-3, 3, width=32))


@settings(max_examples=60, deadline=None)
@given(_sides)
def test_shrinking_footprints_are_those_longer_than_a_pixel_in_some_direction(foot):
    jac = foot.astype(np.float64).reshape(-1, 2, 2).transpose(0, 2, 1)  # columns a, b
    s1 = np.linalg.svd(jac, compute_uv=False)[:, 0]
    clear = np.abs(s1 - SHRINK) > 1e-4  # away from the threshold, where float32 rounding could go either way
    foot, s1 = foot[clear], s1[clear]
    assert band_shrinks(foot, np.ones(len(foot), bool)) == bool(np.any(s1 > SHRINK))
    for k in range(len(foot)):  # each footprint alone, and invalid ones never count
        assert band_shrinks(foot[k:k + 1], np.ones(1, bool)) == bool(s1[k] > SHRINK)
        assert not band_shrinks(foot[k:k + 1], np.zeros(1, bool))


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
