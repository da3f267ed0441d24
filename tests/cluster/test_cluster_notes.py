"""A batch's notes on a Dask cluster are the notes the same batch gives on this machine: a note about the whole
command (--antialias on a view that shrinks the source nowhere) once per command, however many workers ran its
files; a note about one file (colours outside the sRGB gamut, counted in that file) once per file.

The reference is the same command run without a scheduler; the colour counts are worked out here from the
files' own pixels (Display P3 primaries converted to Rec.709 with colour-science's matrices).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from lenslab.cli.main import main as lenslab  # noqa: E402
from lenslab.io import write  # noqa: E402
from lenslab.warp.minification import NOTE  # noqa: E402

pytestmark = pytest.mark.slow

FILES = 8  # more files than workers: each of the two workers gets some (before, each worker said the note once)


@pytest.fixture(scope="module")
def scheduler():
    """The address of a scheduler with two single-threaded worker processes, no dashboard."""
    from lenslab.cluster.connect import local_cluster

    with local_cluster(workers=2, threads=1) as client:
        yield client.scheduler.address


def _panoramas(folder: Path) -> list[Path]:
    folder.mkdir()
    rng = np.random.default_rng(3)
    paths = [folder / f"pano{i}.exr" for i in range(FILES)]
    for path in paths:
        write(path, rng.random((32, 64, 3), dtype=np.float32) * 4, pixel_type="float")
    return paths


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if ": note: " in line]


def test_the_softening_note_comes_once_per_command_on_two_workers(tmp_path, scheduler, capsys):
    _panoramas(tmp_path / "in")
    cmd = ["warp", str(tmp_path / "in"), "--to", "equirect", "--antialias"]  # identity warps: no file shrinks
    assert lenslab(cmd + ["-o", str(tmp_path / "cluster"), "--scheduler", scheduler]) == 0
    remote = capsys.readouterr().err
    assert len(list((tmp_path / "cluster").iterdir())) == FILES
    assert len(_notes(remote)) == 1 and remote.count(NOTE) == 1, remote
    assert lenslab(cmd + ["-o", str(tmp_path / "local"), "--jobs", "2"]) == 0
    local = capsys.readouterr().err
    assert _notes(local) == _notes(remote)  # the same line, naming the batch's first file


def _p3_png(path: Path, rgb: np.ndarray) -> None:
    """An 8-bit PNG tagged Display P3 (cICP: primaries 12, transfer 13 = sRGB's curve), written by hand."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    h, w, _ = rgb.shape
    raw = b"".join(b"\0" + rgb[y].tobytes() for y in range(h))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                     + chunk(b"cICP", bytes([12, 13, 0, 1])) + chunk(b"IDAT", zlib.compress(raw))
                     + chunk(b"IEND", b""))


def _outside_srgb(rgb: np.ndarray) -> int:
    """Pixels of P3 codes whose linear Rec.709 colour has a negative component (float64, colour-science)."""
    import colour

    lin = colour.models.eotf_sRGB(rgb.astype(np.float64) / 255)
    m = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["Display P3"], colour.RGB_COLOURSPACES["sRGB"])
    rec709 = lin @ m.T
    return int(np.count_nonzero((rec709 < -1e-9).any(axis=-1)))


def test_the_gamut_note_comes_once_per_file_on_the_cluster_as_here(tmp_path, scheduler, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    rng = np.random.default_rng(8)
    counts = {}
    for i in range(4):
        rgb = rng.integers(0, 256, (16, 24, 3), dtype=np.uint8)
        rgb[: 4 + i, :, :] = (0, 255, 0)  # saturated P3 green: outside sRGB, a different count in each file
        _p3_png(folder / f"p3_{i}.png", rgb)
        counts[f"p3_{i}.png"] = _outside_srgb(rgb)
    cmd = ["convert", str(folder), "--to", "jpg"]
    assert lenslab(cmd + ["-o", str(tmp_path / "cluster"), "--scheduler", scheduler]) == 0
    remote = _notes(capsys.readouterr().err)
    assert lenslab(cmd + ["-o", str(tmp_path / "local")]) == 0
    local = _notes(capsys.readouterr().err)
    assert sorted(remote) == sorted(local) and len(remote) == 4, remote
    for name, n in counts.items():
        line, = (r for r in remote if f"{name}:" in r)
        assert re.search(rf"\b{n} of {16 * 24} pixels\b", line), line



def test_a_warps_gamut_note_names_the_output_as_given_on_the_cluster_as_here(tmp_path, scheduler, capsys, monkeypatch):
    """The workers get absolute paths; the notes name the files as the command was given them, as here (before, the
    warped image was named by its absolute path on the cluster)."""
    monkeypatch.chdir(tmp_path)
    Path("in").mkdir()
    rng = np.random.default_rng(9)
    counts = {}
    for i in range(3):
        rgb = np.repeat(rng.integers(0, 256, (16, 32, 1), dtype=np.uint8), 3, axis=-1)  # greys: inside any gamut
        rgb[: 2 + i, :, :] = (0, 255, 0)  # saturated P3 green: outside sRGB, in rows of a different count
        _p3_png(Path("in") / f"p3_{i}.png", rgb)
        counts[f"p3_{i}"] = _outside_srgb(rgb)
    # the identity warp with the nearest pixel: each output pixel is its source pixel, the counts the source's
    cmd = ["warp", "in", "-o", "out", "--from", "equirect", "--to", "equirect", "--size", "32x16", "--filter",
           "nearest", "--format", "jpg", "--overwrite"]
    assert lenslab(cmd + ["--scheduler", scheduler]) == 0
    remote = _notes(capsys.readouterr().err)
    assert lenslab(cmd) == 0
    local = _notes(capsys.readouterr().err)
    assert sorted(remote) == sorted(local) and len(remote) == 3, remote
    for name, n in counts.items():
        line, = (r for r in remote if f"{name}.png:" in r)
        assert re.search(rf"\b{n} of {16 * 32} pixels of the warped image out/{name}.jpg ", line), line


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
