"""A warp of one still image keeps no maps (no later image would reuse them; a band's map lives in
scratch memory while it is drawn), a batch keeps its geometry's maps; either way each output is the
warp of its image (lenslab.warp.warp), bit for bit, and OpenImageIO reads the same pixels from both."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write
from lenslab.jobs.warp import WarpJob, plans_for
from lenslab.lenses import Camera
from lenslab.warp import warp

oiio = pytest.importorskip("OpenImageIO")


def _pixels(path):
    inp = oiio.ImageInput.open(str(path))
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    return pixels


def test_one_image_keeps_no_maps_and_a_batch_keeps_them():
    src, dst = Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (24, 24))
    assert plans_for(WarpJob(to="fisheye", keep_maps=False)).plan(src, dst).cache is False
    assert plans_for(WarpJob(to="fisheye")).plan(src, dst).cache is True


def test_one_image_and_a_batch_give_the_warp_of_each_image(tmp_path):
    rng = np.random.default_rng(4)
    img = (rng.random((32, 64, 3)) * 8).astype(np.float32)
    for name in ("a.exr", "b.exr"):
        write(tmp_path / name, img, pixel_type="float")
    opts = ["--to", "fisheye:fov=180", "--size", "24x24", "--pixel-type", "float", "-q"]
    assert main(["warp", str(tmp_path / "a.exr"), "-o", str(tmp_path / "one.exr"), *opts]) == 0
    assert main(["warp", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "-o", str(tmp_path / "batch"), *opts]) == 0
    ref, alpha = warp(img, Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (24, 24)))
    expected = np.concatenate([ref, alpha[..., None]], axis=-1)
    for path in (tmp_path / "one.exr", tmp_path / "batch" / "a.exr", tmp_path / "batch" / "b.exr"):
        assert np.array_equal(_pixels(path), expected), path
