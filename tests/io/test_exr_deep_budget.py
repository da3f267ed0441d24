"""Deep EXR files are held to the input budget by the samples their count tables hold, before OpenEXR
allocates a sample: a small file whose tables declare hundreds of millions of samples fails in one line,
exit 1, within bounded memory. The counts lenslab reads from the tables are OpenEXR's own (its bindings'
samples per pixel), for every compression a deep file may use."""

from __future__ import annotations

import struct
import subprocess
import sys

import numpy as np
import pytest

from lenslab.io.exr.chunks import parse_header
from lenslab.io.exr.deep_counts import deep_counts
from tests.hostile_run import run
from tests.io.deep_files import deep_header

OpenEXR = pytest.importorskip("OpenEXR")
N = 64


def deep_file(path, counts, compression="NO_COMPRESSION", seed=0, tiles=None):
    rng = np.random.default_rng(seed)
    h, w = counts.shape
    chans = {n: np.empty((h, w), dtype=object) for n in ("R", "G", "B", "A", "Z")}
    for (y, x), n in np.ndenumerate(counts):
        if n:
            chans["Z"][y, x] = rng.uniform(1, 9, n).astype(np.float32)
            for c in "RGBA":
                chans[c][y, x] = rng.uniform(0, 1, n).astype(np.float16)
    OpenEXR.File(deep_header(getattr(OpenEXR, compression), tiles), chans).write(str(path))
    return path


@pytest.mark.parametrize("compression", ["NO_COMPRESSION", "RLE_COMPRESSION", "ZIPS_COMPRESSION"])
@pytest.mark.parametrize("tiles", [None, (8, 5)], ids=["scanlines", "tiles"])
def test_the_counts_are_openexr_s(tmp_path, compression, tiles):
    counts = np.random.default_rng(3).integers(0, 5, (13, 21))
    counts[2] = 0  # a line without samples
    path = deep_file(tmp_path / "d.exr", counts, compression, tiles=tiles)
    got = deep_counts(path, parse_header(path))[0]
    pixels = OpenEXR.File(str(path), separate_channels=True).parts[0].channels["Z"].pixels
    lens = np.array([[0 if p is None else len(p) for p in row] for row in pixels])
    assert (got.total, got.max_per_pixel, got.pixels) == (lens.sum(), lens.max(), np.count_nonzero(lens))
    assert got.total == counts.sum()


def bomb(path, per_pixel=100_000, consistent=True):
    """A 64 x 64 deep file of one sample a pixel, uncompressed, whose count tables are rewritten to declare
    ``per_pixel`` samples in every pixel (the chunks' unpacked sizes to match, unless not ``consistent``)."""
    deep_file(path, np.ones((N, N), np.int64))
    layout = parse_header(path)
    data = bytearray(path.read_bytes())
    offsets = struct.unpack_from(f"<{N}Q", data, layout.header_end)
    table = np.arange(1, N + 1, dtype="<i4") * per_pixel
    for off in offsets:
        y, packed_table, packed, unpacked = struct.unpack_from("<iQQQ", data, off)
        assert packed_table == 4 * N and unpacked == 12 * N  # raw tables: A, B, G, R half and Z float
        data[off + 28:off + 28 + 4 * N] = table.tobytes()
        struct.pack_into("<Q", data, off + 20, 12 * N * per_pixel if consistent else unpacked)
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize("command", [["info"], ["convert", "--to", "exr"], ["warp", "--to", "perspective:fov=60"]])
def test_a_small_file_declaring_huge_sample_counts_fails_in_one_line(tmp_path, command):
    src = bomb(tmp_path / "bomb.exr")
    assert src.stat().st_size < 100_000
    out = ["-o", str(tmp_path / "out.exr")] if command[0] != "info" else []
    done = run([sys.executable, "-m", "lenslab", command[0], str(src), *command[1:], *out])
    assert done.returncode == 1, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"lenslab {command[0]}: error: {src}: its deep sample count tables "
                                                   f"hold {N * N * 100_000} samples in {N * N} pixels"), lines
    assert "refused as a decompression bomb" in lines[0]
    assert done.peak_mb is None or done.peak_mb < 200  # nothing of the declared 409 600 000 samples was allocated
    assert not (tmp_path / "out.exr").exists()


def test_a_chunk_whose_sizes_disagree_with_its_table_is_damaged(tmp_path):
    src = bomb(tmp_path / "odd.exr", per_pixel=2, consistent=False)
    done = subprocess.run([sys.executable, "-m", "lenslab", "info", str(src)], capture_output=True, text=True)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        f"lenslab info: error: {src}: a deep chunk of part 0 (line 0) declares {12 * N} bytes of samples but its "
        f"table counts {2 * N} samples of 12 bytes; the file is damaged"]


def test_a_huge_data_window_in_a_small_image_is_refused_before_its_tables_are_read(tmp_path):
    """OpenEXR's bindings make a pointer for every pixel and channel of a deep data window, samples or not:
    a 64 x 64 image whose data window is declared 40000 x 64 is refused from the header alone."""
    src = deep_file(tmp_path / "wide.exr", np.ones((N, N), np.int64))
    data = bytearray(src.read_bytes())
    at = data.index(b"dataWindow\0box2i\0") + len(b"dataWindow\0box2i\0") + 4
    assert struct.unpack_from("<iiii", data, at) == (0, 0, N - 1, N - 1)
    struct.pack_into("<iiii", data, at, 0, 0, 40_000 - 1, N - 1)
    src.write_bytes(bytes(data))
    done = run([sys.executable, "-m", "lenslab", "info", str(src)])
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"lenslab info: error: {src}: its deep data windows take 102 MB "
                                                   "to read in a file of"), lines
    assert done.peak_mb is None or done.peak_mb < 200
