"""Channel counts as the files hold them: a two-channel EXR (grey and alpha) reads as two channels, as
OpenImageIO reads it; RGBE and PPM hold colour only, so their records declare three channels and a grey
image goes in as equal R, G and B."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.registry import formats

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")


def oiio_read(path):
    inp = oiio.ImageInput.open(str(path))
    try:
        spec = inp.spec()
        pixels = np.asarray(inp.read_image("float"), np.float32).reshape(spec.height, spec.width, spec.nchannels)
        return pixels, list(spec.channelnames), spec.alpha_channel
    finally:
        inp.close()


def test_a_grey_and_alpha_exr_reads_as_two_channels(tmp_path):
    y = np.random.default_rng(0).random((4, 5)).astype(np.float32)
    a = np.full((4, 5), 0.5, np.float32)
    path = tmp_path / "ya.exr"
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"Y": y, "A": a}).write(str(path))  # written by OpenEXR itself, not by lenslab
    theirs, names, alpha = oiio_read(path)
    assert names == ["Y", "A"] and alpha == 1  # OpenImageIO: two channels, the second alpha
    ours, meta = lio.read(path)
    assert meta["channels"] == ["Y", "A"] and ours.shape == (4, 5, 2)
    np.testing.assert_array_equal(ours, theirs)
    # and lenslab writes a two-channel image as Y and A, which OpenImageIO reads back the same
    back = lio.write(tmp_path / "again.exr", ours, pixel_type="float")
    theirs, names, _ = oiio_read(back)
    assert names == ["Y", "A"]
    np.testing.assert_array_equal(theirs, ours)


@pytest.mark.parametrize("name, ext", [("hdr", ".hdr"), ("ppm", ".ppm")])
def test_colour_only_formats_declare_three_channels_and_take_grey_as_rgb(tmp_path, name, ext):
    assert formats()[name].channels == (3,)
    grey = np.linspace(0.1, 0.9, 20, dtype=np.float32).reshape(4, 5, 1)
    path = lio.write(tmp_path / f"g{ext}", grey)
    ours, meta = lio.read(path)
    assert ours.shape == (4, 5, 3) and len(meta["channels"]) == 3
    theirs, names, _ = oiio_read(path)
    assert len(names) == 3  # what OpenImageIO finds in the file
    np.testing.assert_array_equal(ours[..., 0], ours[..., 1])
    np.testing.assert_array_equal(ours[..., 0], ours[..., 2])


def test_grey_to_pnm_is_still_a_pgm(tmp_path):
    grey = np.linspace(0.1, 0.9, 20, dtype=np.float32).reshape(4, 5, 1)
    _, meta = lio.read(lio.write(tmp_path / "g.pnm", grey))
    assert meta["format"] == "pgm"
    alpha = np.concatenate([grey, np.ones_like(grey)], axis=2)
    _, meta = lio.read(lio.write(tmp_path / "ga.pnm", alpha))
    assert meta["format"] == "pgm" and meta["channels"] == ["Y"]
