"""Byte mutations of small deep EXR files (one part uncompressed, RLE or ZIP; two deep parts; deep tiles): the header,
the offset tables, the chunk leaders and the sample count tables. Each mutated file, read in a subprocess
under an address-space limit, gives an image or a one-line lenslab error: never another exception, a crash,
a hang or an allocation the budget did not admit."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.hostile_run import read_many
from tests.io.test_hostile_mutations import BIG, SETTINGS, assert_read_or_refused

OpenEXR = pytest.importorskip("OpenEXR")


def channels(h, w, seed):
    rng = np.random.default_rng(seed)
    chans = {n: np.empty((h, w), dtype=object) for n in ("R", "G", "B", "A", "Z")}
    for (y, x), n in np.ndenumerate(rng.integers(0, 4, (h, w))):
        if n:
            chans["Z"][y, x] = rng.uniform(1, 9, n).astype(np.float32)
            for c in "RGBA":
                chans[c][y, x] = rng.uniform(0, 1, n).astype(np.float16)
    return chans


def seeds(folder) -> list[bytes]:
    out = []
    for i, comp in enumerate(("NO_COMPRESSION", "RLE_COMPRESSION", "ZIPS_COMPRESSION")):
        path = folder / f"seed-{i}.exr"
        OpenEXR.File({"compression": getattr(OpenEXR, comp), "type": OpenEXR.deepscanline},
                     channels(6, 8, i)).write(str(path))
        out.append(path.read_bytes())
    head = {"compression": OpenEXR.ZIPS_COMPRESSION, "type": OpenEXR.deepscanline}
    parts = [OpenEXR.Part({**head, "name": f"rgba.{v}", "view": v}, channels(5, 7, 9 + k), f"rgba.{v}")
             for k, v in enumerate(("left", "right"))]
    path = folder / "seed-stereo.exr"
    OpenEXR.File(parts).write(str(path))
    out.append(path.read_bytes())
    tiles = OpenEXR.TileDescription()
    tiles.xSize, tiles.ySize = 4, 3
    path = folder / "seed-tiles.exr"
    OpenEXR.File({"compression": OpenEXR.NO_COMPRESSION, "type": OpenEXR.deeptile, "tiles": tiles},
                 channels(7, 9, 5)).write(str(path))
    return out + [path.read_bytes()]


@st.composite
def mutated(draw, data: bytes) -> bytes:
    b = bytearray(data)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["byte", "word", "long", "cut"]))
        at = draw(st.integers(0, max(len(b) - 8, 0)))
        if op == "byte" and b:
            b[at] = draw(st.integers(0, 255))
        elif op == "word" and len(b) >= at + 4:
            b[at:at + 4] = struct.pack("<I", draw(st.sampled_from(BIG)))
        elif op == "long" and len(b) >= at + 8:  # sizes and offsets are uint64
            b[at:at + 8] = struct.pack("<Q", draw(st.sampled_from(BIG + [1 << 40, (1 << 64) - 1])))
        elif op == "cut":
            b = b[:at]
    return bytes(b)


def test_the_seeds_are_read(tmp_path):
    paths = []
    for i, seed in enumerate(seeds(tmp_path)):
        paths.append(tmp_path / f"ok-{i}.exr")
        paths[-1].write_bytes(seed)
    done = read_many("image", paths)
    assert done.stdout.count("OK ") == len(paths), done.stdout


@SETTINGS
@given(data=st.data())
def test_mutated_deep_files_are_read_or_refused_in_one_line(tmp_path_factory, data):
    folder = tmp_path_factory.mktemp("deepmut")
    paths = []
    for i, seed in enumerate(seeds(folder)):
        for k in range(10):
            p = folder / f"deep-{i}-{k}.exr"
            p.write_bytes(data.draw(mutated(seed), label=p.name))
            paths.append(p)
    assert_read_or_refused(read_many("image", paths), paths)
