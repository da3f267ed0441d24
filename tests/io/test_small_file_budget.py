"""The small-file budget (lenslab.io.budget: any file may decode to 96 MiB of float32, a file under 1 MiB
to 512 times its bytes when that is more) admits what people share on the web, a 4096 x 2048 RGB panorama
whatever its file, larger smooth panoramas from files of their size, and refuses in one line a flat file
that passes it, naming the LENSLAB_BASE_BYTES value that admits the file. Files written by OpenCV (the
outside encoder) and read back by it for the sizes; OpenImageIO reads the converted file."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

import lenslab
from lenslab.io.budget import BudgetError
from tests.hostile_run import run

cv2 = pytest.importorskip("cv2")
oiio = pytest.importorskip("OpenImageIO")

SMALL_FILE = 1 << 20


def _panorama(h, w, c, noisy_rows=0):
    """8-bit codes of a smooth panorama (BGR(A) as OpenCV writes them), alpha a smooth ramp; the first
    ``noisy_rows`` rows random (a file that does not compress to under 1 MB)."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    planes = [x / w, y / h, 0.5 + 0.0 * x] + ([1.0 - y / (2 * h)] if c == 4 else [])
    img = (np.stack(planes, axis=-1) * 255).astype(np.uint8)
    img[:noisy_rows] = np.random.default_rng(0).integers(0, 256, img[:noisy_rows].shape, dtype=np.uint8)
    return img


def _flat(h, w, c):
    """8-bit codes of one grey: a PNG of a few kB."""
    return np.full((h, w, c), 128, np.uint8)


def _write(tmp_path, name, img):
    path = tmp_path / name
    assert cv2.imwrite(str(path), img)
    return path


def test_a_4096_x_2048_rgb_png_under_1_mb_is_read_and_warped(tmp_path):
    path = _write(tmp_path, "pano.png", _panorama(2048, 4096, 3))
    assert path.stat().st_size < SMALL_FILE
    pixels, meta = lenslab.read(path)
    assert pixels.shape == cv2.imread(str(path)).shape == (2048, 4096, 3)
    out = tmp_path / "fish.exr"
    done = run([sys.executable, "-m", "lenslab", "warp", str(path), "-o", str(out), "--to", "fisheye:fov=180",
                "--size", "256x256", "-q"])
    assert done.returncode == 0, done.stderr
    assert out.is_file()


@pytest.mark.parametrize("h,w,c", [(2048, 4096, 4), (2049, 4096, 3)])
def test_more_than_4096_x_2048_rgb_from_a_flat_file_is_refused_in_one_line(tmp_path, h, w, c):
    path = _write(tmp_path, "big.png", _flat(h, w, c))
    assert 512 * path.stat().st_size < 96 << 20  # the file's own budget is below the base: 96 MiB it is
    assert cv2.imread(str(path), cv2.IMREAD_UNCHANGED).shape == (h, w, c)
    with pytest.raises(BudgetError) as caught:
        lenslab.read(path)
    message = str(caught.value)
    assert "\n" not in message and "101 MB" in message and f"LENSLAB_BASE_BYTES={w * h * c * 4}" in message


@pytest.mark.parametrize("h,w,c", [(2048, 4096, 4), (2049, 4096, 3)])
def test_more_than_4096_x_2048_rgb_from_a_smooth_panorama_under_1_mb_is_read(tmp_path, h, w, c):
    """The same sizes as a smooth panorama: 0.66 MB, within 512 times its bytes."""
    path = _write(tmp_path, "big.png", _panorama(h, w, c))
    size = path.stat().st_size
    assert size < SMALL_FILE and 96 << 20 < w * h * c * 4 <= 512 * size
    pixels, _ = lenslab.read(path)
    assert pixels.shape == cv2.imread(str(path), cv2.IMREAD_UNCHANGED).shape == (h, w, c)


def test_a_flat_rgba_panorama_converts_with_the_value_the_refusal_names(tmp_path):
    path = _write(tmp_path, "rgba.png", _flat(2048, 4096, 4))
    out = tmp_path / "out.exr"
    argv = [sys.executable, "-m", "lenslab", "convert", str(path), "--to", "exr", "-o", str(out), "-q"]
    done = run(argv)
    assert done.returncode == 1 and not out.exists()
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    done = run(argv, env=dict(os.environ, LENSLAB_BASE_BYTES=str(4096 * 2048 * 4 * 4)))
    assert done.returncode == 0, done.stderr
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    inp.close()
    assert (spec.width, spec.height, spec.nchannels) == (4096, 2048, 4)


def test_the_same_rgba_panorama_in_a_file_over_1_mb_is_read(tmp_path):
    """The rule is about bytes: 128 MiB from a file of a few MB is within 512 times its first MiB and 4096
    times the rest."""
    path = _write(tmp_path, "rgba-noisy.png", _panorama(2048, 4096, 4, noisy_rows=96))
    size = path.stat().st_size
    assert size > SMALL_FILE and 4096 * 2048 * 4 * 4 <= 512 * SMALL_FILE + 4096 * (size - SMALL_FILE)
    pixels, _ = lenslab.read(path)
    assert pixels.shape == (2048, 4096, 4)
