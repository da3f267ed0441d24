"""A half EXR of channels other than R, G, B (A) (grey and alpha: a warped grey panorama) made in the image's own
memory has its planes laid out in that memory too: an 8192 x 4096 grey warp's write peaked 136 MB above its warp
(the two planes copied out of the halves) where an RGBA one adds nothing. The file is what OpenImageIO reads as
NumPy's halves of the image."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from lenslab.io.exr import write_exr


@pytest.mark.parametrize("channels", [["Y", "A"], ["G", "A"], ["Y", "Z", "A"]])
def test_planes_of_an_in_place_half_write_are_read_by_openimageio(tmp_path, channels):
    import OpenImageIO as oiio

    rng = np.random.default_rng(7)
    image = (rng.standard_normal((96, 160, len(channels))) * 300).astype(np.float32)
    image[0, 0, 0] = 70000.0  # beyond half: clamped to 65504
    want = np.clip(image, -65504, 65504).astype(np.float16)  # NumPy's halves, taken before the image is given up
    write_exr(tmp_path / "o.exr", image, channels=channels, in_place=True)
    buf = oiio.ImageBuf(str(tmp_path / "o.exr"))
    got = buf.get_pixels(oiio.HALF)
    order = [buf.spec().channelnames.index(n) for n in channels]
    np.testing.assert_array_equal(got[..., order].view(np.uint16), want.view(np.uint16))


def test_a_float_write_in_place_keeps_its_values(tmp_path):
    """A float32 file given up by its caller is not laid out as halves: OpenImageIO reads the floats."""
    import OpenImageIO as oiio

    image = np.linspace(-1e6, 1e6, 64 * 32 * 2, dtype=np.float32).reshape(64, 32, 2)
    want = image.copy()
    write_exr(tmp_path / "f.exr", image, pixel_type="float", channels=["Y", "A"], in_place=True)
    buf = oiio.ImageBuf(str(tmp_path / "f.exr"))
    got = buf.get_pixels(oiio.FLOAT)
    np.testing.assert_array_equal(got[..., [buf.spec().channelnames.index(n) for n in ("Y", "A")]], want)


def test_an_in_place_grey_alpha_write_allocates_no_plane_of_the_image(tmp_path):
    image = np.ones((512, 1024, 2), np.float32)
    size = image.nbytes  # (the image is given up: its memory holds the halves and planes after the write)
    tracemalloc.start()
    try:
        write_exr(tmp_path / "o.exr", image, channels=["Y", "A"], in_place=True)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    # the two half planes copied out were half the float image (1 MiB each); what is left is small bookkeeping
    assert peak < size // 16, peak
