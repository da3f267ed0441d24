"""What :func:`lenslab.read` gives for an EXR can be pickled and deep-copied, as for every other format: a Dask
task that returns ``(image, meta)`` sends it back to the client by pickling, and a user copies ``meta`` before
changing it. The part's header kept for an EXR writer (``meta["exr_header"]``, OpenEXR's own objects, some of
which the bindings cannot pickle: channel lists, tile descriptions) travels with what can be pickled of it.
Expected values: OpenEXR's own reading of the file's header."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.exr.keep import kept_header


@pytest.fixture
def tiled(tmp_path):
    path = tmp_path / "tiled.exr"
    tiles = OpenEXR.TileDescription()
    tiles.xSize, tiles.ySize, tiles.mode = 4, 4, OpenEXR.ONE_LEVEL
    rgb = np.random.default_rng(1).random((8, 12, 3)).astype(np.float32)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.tiledimage, "tiles": tiles,
                  "owner": "lenslab", "capDate": "2026:11:27 01:00:00"},
                 {"RGB": rgb, "Z": rgb[..., 0].copy()}).write(str(path))
    return path


@pytest.mark.parametrize("send", [lambda m: pickle.loads(pickle.dumps(m)), copy.deepcopy], ids=["pickle", "deepcopy"])
def test_exr_meta_pickles_and_copies(tiled, send):
    image, meta = lio.read(tiled, data_window=True, extra_channels=True)
    got = send(meta)
    header = OpenEXR.File(str(tiled), header_only=True).parts[0].header
    assert got["exr_header"]["owner"] == header["owner"] == "lenslab"
    for key in ("channels", "data_window", "display_window", "extra_channels", "attributes", "storage"):
        assert got[key] == meta[key], key
    np.testing.assert_array_equal(got["extra_planes"]["Z"], meta["extra_planes"]["Z"])
    # what an EXR writer keeps of the header, from the copy: the shot's attributes, as OpenEXR read them
    kept = kept_header(got, ["R", "G", "B", "Z"])["attributes"]
    assert kept["owner"] == header["owner"] and kept["capDate"] == header["capDate"]
    # the original keeps OpenEXR's own objects for this process's writer
    assert meta["exr_header"]["tiles"].xSize == header["tiles"].xSize == 4
