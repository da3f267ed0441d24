"""EXR to EXR keeps the data window where the input stores it, inside, beyond or apart from the display
window, as OpenImageIO (and oiiotool) keep it: no depth of 0 is made up outside the stored pixels. The
values expected are OpenImageIO's reading of the input."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")
OpenEXR = pytest.importorskip("OpenEXR")


def oiio_read(path):
    inp = oiio.ImageInput.open(str(path))
    try:
        spec = inp.spec()
        pixels = inp.read_image(format="float")
    finally:
        inp.close()
    windows = ((spec.x, spec.y, spec.width, spec.height), (spec.full_x, spec.full_y, spec.full_width, spec.full_height))
    return windows, dict(zip(spec.channelnames, np.moveaxis(pixels, -1, 0)))


def depth_render(path):
    """R, G, B, A half and Z float in a data window that crosses the display window's left edge."""
    rng = np.random.default_rng(3)
    h, w = 12, 20
    chans = {c: rng.uniform(0.1, 1, (h, w)).astype(np.float16) for c in "RGBA"}
    chans["Z"] = rng.uniform(2, 50, (h, w)).astype(np.float32)
    header = {"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION,
              "dataWindow": (np.array([-4, 6], np.int32), np.array([-4 + w - 1, 6 + h - 1], np.int32)),
              "displayWindow": (np.array([0, 0], np.int32), np.array([31, 23], np.int32))}
    OpenEXR.File(header, chans).write(str(path))
    return path


def test_a_render_keeps_its_data_window_and_every_depth(tmp_path):
    src = depth_render(tmp_path / "render.exr")
    out = tmp_path / "out.exr"
    assert main(["convert", str(src), "--to", "exr", "-o", str(out), "-q"]) == 0
    (win, full), want = oiio_read(src)
    (owin, ofull), got = oiio_read(out)
    assert (owin, ofull) == (win, full) == ((-4, 6, 20, 12), (0, 0, 32, 24))
    assert set(got) == set(want)
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)
    assert got["Z"].min() >= 2  # no 0 depth outside the stored pixels


@pytest.mark.parametrize("name", ["openexr-images/DisplayWindow/t05.exr", "openexr-images/DisplayWindow/t09.exr",
                                  "oiio-images/grid-overscan.exr"])
def test_shared_files_keep_their_windows(shared_data, tmp_path, name):
    src = shared_data / "formats" / name
    out = tmp_path / "out.exr"
    assert main(["convert", str(src), "--to", "exr", "-o", str(out), "-q"]) == 0
    (win, full), want = oiio_read(src)
    (owin, ofull), got = oiio_read(out)
    assert (owin, ofull) == (win, full)
    for channel in want:
        np.testing.assert_array_equal(got[channel], want[channel], err_msg=channel)


def test_placing_is_still_there_for_formats_without_windows(tmp_path):
    src = depth_render(tmp_path / "render.exr")
    assert main(["convert", str(src), "--to", "tiff", "-o", str(tmp_path / "out.tif"), "-q"]) == 0
    (win, full), want = oiio_read(src)
    got = oiio.ImageBuf(str(tmp_path / "out.tif")).get_pixels(oiio.FLOAT)
    assert got.shape[:2] == (24, 32)  # the display window, the data window placed in it
    np.testing.assert_array_equal(got[6:18, 0:16, 0], want["R"][:, 4:])  # columns -4 .. -1 lie outside
    assert not got[:6].any() and not got[18:].any() and not got[:, 16:].any()
