"""Decompression bombs (lenslab.bench.bombs): one valid flat-colour file under 1 MB for every registered
format that compresses; each is run through ``lenslab convert`` by tests/io/test_hostile_inputs.py (a
subprocess under an address-space limit, its peak memory against the 200 MB aim). Here: the registry
is covered, the bombs are what outside readers say they are, and the limit can be raised for a genuine
flat image."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

from lenslab.bench.bombs import BOMBS, BOUNDED, RAW, write_bombs
from lenslab.io.registry import formats
from tests.hostile_run import run

oiio = pytest.importorskip("OpenImageIO")

#: lenslab.io.budget: a file under 1 MiB decodes to at most the larger of 96 MiB of float32 (a 4096 x 2048 RGB
#: panorama) and 512 times its bytes
SMALL_FILE, BASE_BYTES, SMALL_RATIO = 1 << 20, 96 << 20, 512


@pytest.fixture(scope="module")
def bombs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bombs")
    return folder, write_bombs(folder)


def test_every_registered_format_that_compresses_has_a_bomb():
    readable = {f.name for f in formats().values() if f.read is not None}
    assert readable == set(BOMBS) | set(RAW) | set(BOUNDED)


def _outside_size(path):
    """(width, height) as the format's reference reader sees it: PyAV (FFmpeg's ISO media demuxer) for a clip and
    a HEIC (OpenImageIO here has no HEIF reader), OpenImageIO otherwise."""
    if path.suffix in (".mp4", ".heic"):
        import av

        with av.open(str(path)) as clip:
            s = clip.streams.video[0]
            return s.width, s.height
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    inp.close()
    return spec.width, spec.height


def test_each_bomb_is_a_valid_file_under_1_mb_that_decodes_beyond_the_limit(bombs):
    folder, made = bombs
    for name, size in made.items():
        path = folder / name
        assert path.stat().st_size < SMALL_FILE, name
        assert _outside_size(path) == size, name
        assert size[0] * size[1] * 3 * 4 > max(BASE_BYTES, SMALL_RATIO * path.stat().st_size), name  # float32 RGB


def test_the_flattest_radiance_file_is_read_within_its_bytes(tmp_path):
    """Radiance run lengths code at most 127 pixels of a component in 2 bytes: a 3800 x 3800 file of runs
    of black is 0.93 MB (3800 * (4 + 4 * 30 * 2) bytes of scanlines) for 173 MB of float, 186 times its
    bytes, under the 512 the budget allows; no Radiance file can be a bomb. It converts, and OpenImageIO
    reads black in the EXR written."""
    from lenslab.bench.bombs import flat_hdr

    src = tmp_path / "flat.hdr"
    flat_hdr(src)
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 3800 +X 3800\n"
    assert src.stat().st_size == len(header) + 3800 * (4 + 4 * 30 * 2)  # 30 runs: 29 of 127 and one of 117
    out = tmp_path / "out.exr"
    done = run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", "exr", "-o", str(out), "-q"])
    assert done.returncode == 0, done.stderr
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    assert (spec.width, spec.height) == (3800, 3800)
    assert not pixels.any()  # RGBE (0, 0, 0, 0) is black (Ward, Graphics Gems II)


def test_the_edge_file_decodes_to_the_budget_and_is_admitted(tmp_path):
    """The benchmark's edge file (lenslab.bench.bombs.write_edge, written by OpenEXR) is under 1 MB, is
    the size OpenImageIO reads, a 2:1 panorama that decodes to at most the 96 MiB budget, the next 2:1
    size to more; a convert of it succeeds and OpenImageIO reads its zeros back."""
    from lenslab.bench.bombs import edge_size, write_edge

    path = write_edge(tmp_path / "edge.exr")
    w, h = edge_size()
    assert path.stat().st_size < SMALL_FILE
    assert _outside_size(path) == (w, h) and w == 2 * h  # 2:1, as an equirect
    assert w * h * 4 * 4 <= BASE_BYTES < (w + 2) * (h + 1) * 4 * 4  # RGBA float32
    out = tmp_path / "out.exr"
    done = run([sys.executable, "-m", "lenslab", "convert", str(path), "--to", "exr", "-o", str(out), "-q"])
    assert done.returncode == 0, done.stderr
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    inp.close()
    assert (spec.width, spec.height, spec.nchannels) == (w, h, 4)


def test_a_flat_6k_float_exr_is_refused_and_admitted_as_the_refusal_says(tmp_path):
    """A flat 6144 x 3072 RGB float EXR written by OpenEXR (ZIP: 235 kB) decodes to 226 MB, over the
    budget of its file (512 times its bytes, 120 MB): refused in one line that names the LENSLAB_BASE_BYTES
    value that admits it; with that value it converts and OpenImageIO reads its colour back."""
    import OpenEXR

    src = tmp_path / "flat.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, {"RGB": np.full((3072, 6144, 3), 0.25, np.float32)}).write(str(src))
    assert src.stat().st_size < SMALL_FILE and _outside_size(src) == (6144, 3072)
    need = 6144 * 3072 * 3 * 4
    out = tmp_path / "out.exr"
    argv = [sys.executable, "-m", "lenslab", "convert", str(src), "--to", "exr", "-o", str(out), "-q"]
    done = run(argv)
    assert done.returncode == 1 and not out.exists()
    lines = done.stderr.strip().splitlines()
    allowed = SMALL_RATIO * src.stat().st_size
    assert need > allowed > BASE_BYTES
    assert len(lines) == 1 and f"LENSLAB_BASE_BYTES={need}" in lines[0], done.stderr
    assert f"at most {allowed / 1e6:.3g} MB" in lines[0], done.stderr
    done = run(argv, env=dict(os.environ, LENSLAB_BASE_BYTES=str(need)))
    assert done.returncode == 0, done.stderr
    inp = oiio.ImageInput.open(str(out))
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    assert pixels.shape == (3072, 6144, 3) and np.all(pixels == np.float32(0.25))  # 0.25: exact in half


def test_a_web_panorama_jpeg_under_1_mb_is_read(tmp_path):
    """A 4096 x 2048 JPEG of a smooth panorama, as shared on the web, is under 1 MB and decodes to 101 MB of
    float: within the small-file budget, so it is read (OpenCV, the outside decoder, gives the same size)."""
    import cv2

    import lenslab

    y, x = np.mgrid[0:2048, 0:4096].astype(np.float32)
    img = np.stack([x / 4096, y / 2048, 0.5 + 0.0 * x], axis=-1) * 255
    path = tmp_path / "pano.jpg"
    assert cv2.imwrite(str(path), img.astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, 80])
    assert path.stat().st_size < SMALL_FILE
    assert 4096 * 2048 * 3 * 4 <= BASE_BYTES
    pixels, _ = lenslab.read(path)
    assert pixels.shape == cv2.imread(str(path)).shape == (2048, 4096, 3)
