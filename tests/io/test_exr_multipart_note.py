"""A multi-part EXR read without a selector: part 0, as OpenImageIO's default subimage, and one note that
names the parts and how to pick another."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main
from lenslab.io.exr import MultiPartWarning

OpenEXR = pytest.importorskip("OpenEXR")


def multipart(path):
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    a = np.arange(20, dtype=np.float32).reshape(4, 5)
    parts = [OpenEXR.Part({**h, "name": "beauty"}, {"R": a, "G": 2 * a, "B": 3 * a}, "beauty"),
             OpenEXR.Part({**h, "name": "depth"}, {"Z": 7 * a}, "depth")]
    OpenEXR.File(parts).write(str(path))
    return path


def test_part_0_is_read_with_a_note_naming_the_parts(tmp_path):
    p = multipart(tmp_path / "m.exr")
    with pytest.warns(MultiPartWarning) as caught:
        img, meta = lio.read(p)
    msg = str(caught[0].message)
    assert "2 parts" in msg and "0: 'beauty'" in msg and "1: 'depth'" in msg and "m.exr:NAME" in msg
    oiio = pytest.importorskip("OpenImageIO")
    buf = oiio.ImageBuf(str(p))  # OpenImageIO's default: subimage 0
    assert buf.nsubimages == 2
    np.testing.assert_array_equal(img, buf.get_pixels(oiio.FLOAT))
    assert meta["part"] == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a selector says which part: no note
        img, _ = lio.read(f"{p}:depth")
    np.testing.assert_array_equal(img[..., 0], 7 * np.arange(20, dtype=np.float32).reshape(4, 5))


def test_a_command_prints_the_note_once(tmp_path, capsys):
    p = multipart(tmp_path / "m.exr")
    assert main(["convert", str(p), "--to", "pfm", "-o", str(tmp_path / "m.pfm")]) == 0
    err = capsys.readouterr().err
    assert err.count("has 2 parts") == 1, err
