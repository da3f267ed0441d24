"""Phone photos are read; flat files of the same 12 megapixels are refused before any pixel memory.

A 12 MP (4032 x 3024) image decodes to 146 MB of float32, more than the 96 MiB any file may decode to, so
a photo is read when its file holds at least 1/512 of that (lenslab.io.budget.SMALL_RATIO): 286 kB. The
genuine photo is a view of a real panorama (../shared/data/hdri) or, where that folder is absent, noise
shaped to a photo's spectrum, encoded by OpenCV (libjpeg) at quality 90; OpenCV reads it back for the
size. The flat files are encoded by OpenCV, Pillow and pillow-heif; each is read in a child process whose
address space may grow by 24 MB only (less than the 36 MB of its 8-bit pixels, a quarter of its float
image), and whose Python allocations (tracemalloc: NumPy's arrays among them) stay under 4 MB (the
header and tables read, about 1 MB for the JPEG)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import lenslab
from tests.conftest import SHARED_DATA
from tests.hostile_run import run

cv2 = pytest.importorskip("cv2")
pillow_heif = pytest.importorskip("pillow_heif")

W, H = 4032, 3024
FLOAT_BYTES = W * H * 3 * 4  # 146 313 216
BASE = 96 << 20


def _photo(tmp_path) -> np.ndarray:
    """8-bit RGB of a real scene: a 70-degree view of a real panorama, else noise of a photo's spectrum."""
    pano = SHARED_DATA / "hdri" / "courtyard.exr"
    if pano.is_file():
        view = tmp_path / "view.png"
        done = run([sys.executable, "-m", "lenslab", "warp", str(pano), "-o", str(view), "--to",
                    "perspective:fov=70", "--size", f"{W}x{H}", "--exposure", "auto", "--no-alpha", "-q"])
        assert done.returncode == 0, done.stderr
        return cv2.cvtColor(cv2.imread(str(view)), cv2.COLOR_BGR2RGB)
    rng = np.random.default_rng(1)
    fy, fx = np.fft.fftfreq(H)[:, None], np.fft.rfftfreq(W)[None, :]
    # natural images fall as 1/f to 1/f^2 in amplitude; 1/f^1.75 at quality 90 gives 0.86 MB, as a phone's
    # 12 MP JPEG of a plain scene
    amplitude = 1.0 / np.maximum(np.hypot(fx, fy), 1.0 / W) ** 1.75
    planes = [np.fft.irfft2(amplitude * np.exp(2j * np.pi * rng.random(amplitude.shape)), s=(H, W))
              for _ in range(3)]
    img = np.stack(planes, axis=-1)
    img = (img - img.mean()) / (4 * img.std()) + 0.5
    return (np.clip(img, 0, 1) * 255).astype(np.uint8)


def test_a_genuine_12_mp_jpeg_under_1_mb_is_read(tmp_path):
    path = tmp_path / "photo.jpg"
    assert cv2.imwrite(str(path), cv2.cvtColor(_photo(tmp_path), cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, 90])
    size = path.stat().st_size
    assert size < 1 << 20 and FLOAT_BYTES > BASE  # what the budget refused from every file under 1 MiB
    assert FLOAT_BYTES <= 512 * size  # this photo compresses less than R = 512 allows
    pixels, meta = lenslab.read(path)
    assert pixels.shape == cv2.imread(str(path)).shape == (H, W, 3)


CHILD = r"""
import resource, sys, tracemalloc
import lenslab
from lenslab.io.budget import BudgetError
for warm in sys.argv[2:]:  # small valid files of the same format: every module a read needs is loaded
    lenslab.read(warm)
vm = next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmSize")) * 1024
resource.setrlimit(resource.RLIMIT_AS, (vm + (24 << 20), resource.RLIM_INFINITY))
tracemalloc.start()
try:
    lenslab.read(sys.argv[1])
    print("READ")
except BudgetError as exc:
    print("REFUSED", tracemalloc.get_traced_memory()[1], str(exc).count("\n"))
"""


def _flat(path, kind: str) -> None:
    from PIL import Image

    img = np.zeros((H, W, 3), np.uint8) + np.array([200, 120, 60], np.uint8)
    if kind == "jpeg-opencv":
        assert cv2.imwrite(str(path), img)  # baseline, 4:2:0, libjpeg's tables
    elif kind == "jpeg-progressive":
        Image.fromarray(img).save(path, progressive=True, optimize=True)
    else:
        pillow_heif.from_bytes("RGB", (W, H), img.tobytes()).save(str(path))  # pillow-heif's default quality


@pytest.mark.parametrize("kind, suffix", [("jpeg-opencv", ".jpg"), ("jpeg-progressive", ".jpg"), ("heic", ".heic")])
def test_a_flat_12_mp_file_is_refused_before_any_pixel_memory(tmp_path, kind, suffix):
    path, warm = tmp_path / f"flat{suffix}", tmp_path / f"warm{suffix}"
    _flat(path, kind)
    assert FLOAT_BYTES > 512 * path.stat().st_size  # flatter than any photo (see lenslab/io/budget.py)
    small = np.full((64, 64, 3), 90, np.uint8)
    if suffix == ".jpg":
        assert cv2.imwrite(str(warm), small)
    else:
        pillow_heif.from_bytes("RGB", (64, 64), small.tobytes()).save(str(warm))
    done = subprocess.run([sys.executable, "-c", CHILD, str(path), str(warm)], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    word, traced, newlines = done.stdout.split()
    assert word == "REFUSED" and newlines == "0"
    assert int(traced) < 4 << 20, traced  # (the reads of the header and tables: a tenth of the 36 MB of codes)
