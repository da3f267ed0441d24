"""EXR to EXR keeps each channel's stored type: half colour beside a float depth stays half, as
OpenImageIO reads both files; an explicit --pixel-type still sets the colour's type."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")


def oiio_formats(path) -> dict[str, str]:
    """{channel: pixel type} as OpenImageIO reads the file (its own decoder, not lenslab's)."""
    inp = oiio.ImageInput.open(str(path))
    try:
        spec = inp.spec()
        formats = spec.channelformats or [spec.format] * spec.nchannels  # (empty when all are alike)
        return dict(zip(spec.channelnames, (str(t) for t in formats)))
    finally:
        inp.close()


def oiio_pixels(path) -> dict[str, np.ndarray]:
    buf = oiio.ImageBuf(str(path))
    px = buf.get_pixels(oiio.FLOAT)
    return {n: px[..., i] for i, n in enumerate(buf.spec().channelnames)}


def make(path, types: dict[str, type]):
    rng = np.random.default_rng(7)
    chans = {}
    for name, dtype in types.items():
        plane = rng.uniform(0, 1, (6, 9))
        if name == "Z" and dtype is np.float32:
            plane = plane * 1e5 + 0.125  # beyond half's range: only a float channel holds it
        if dtype is np.uint32:
            plane = rng.integers(0, 1 << 20, (6, 9))
        chans[name] = plane.astype(dtype)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, chans).write(str(path))
    return path


RENDER = {"R": np.float16, "G": np.float16, "B": np.float16, "A": np.float16, "Z": np.float32}


def test_half_colour_beside_float_depth_stays_half(tmp_path):
    src = make(tmp_path / "rgbaz.exr", RENDER)
    assert main(["convert", str(src), "--to", "exr", "-o", str(tmp_path / "out.exr"), "-q"]) == 0
    assert oiio_formats(tmp_path / "out.exr") == oiio_formats(src) == {
        "R": "half", "G": "half", "B": "half", "A": "half", "Z": "float"}
    a, b = oiio_pixels(src), oiio_pixels(tmp_path / "out.exr")
    for name in RENDER:  # every value as OpenImageIO reads it from the input: nothing narrowed or widened
        np.testing.assert_array_equal(b[name], a[name], err_msg=name)


def test_each_colour_channel_keeps_its_own_type(tmp_path):
    types = {"R": np.float16, "G": np.float32, "B": np.uint32, "A": np.float16, "Z": np.float16}
    src = make(tmp_path / "mixed.exr", types)
    assert main(["convert", str(src), "--to", "exr", "-o", str(tmp_path / "out.exr"), "-q"]) == 0
    assert oiio_formats(tmp_path / "out.exr") == oiio_formats(src) == {
        "R": "half", "G": "float", "B": "uint", "A": "half", "Z": "half"}
    a, b = oiio_pixels(src), oiio_pixels(tmp_path / "out.exr")
    for name in types:  # uint values below 2**24 are exact in lenslab's float32 image
        np.testing.assert_array_equal(b[name], a[name], err_msg=name)


def test_an_explicit_pixel_type_sets_the_colour_and_extra_channels_keep_theirs(tmp_path):
    src = make(tmp_path / "rgbaz.exr", RENDER)
    assert main(["convert", str(src), "--to", "exr", "--pixel-type", "float", "-o", str(tmp_path / "f.exr"),
                 "-q"]) == 0
    assert oiio_formats(tmp_path / "f.exr") == {"R": "float", "G": "float", "B": "float", "A": "float", "Z": "float"}
    depth = {"R": np.float16, "G": np.float16, "B": np.float16, "Z": np.float32}
    src = make(tmp_path / "rgbz.exr", depth)
    assert main(["convert", str(src), "--to", "exr", "--pixel-type", "half", "-o", str(tmp_path / "h.exr"),
                 "-q"]) == 0
    assert oiio_formats(tmp_path / "h.exr") == {"R": "half", "G": "half", "B": "half", "Z": "float"}


def test_mixed_types_clamp_half_channels_in_one_note(tmp_path):
    import warnings

    import lenslab
    from lenslab.io.halves import HalfOverflowWarning

    image = np.full((3, 4, 3), 1e5, np.float32)  # beyond half's 65504 in every channel
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lenslab.write(tmp_path / "m.exr", image, channels=["R", "G", "Z"], pixel_type=["half", "half", "float"])
    notes = [w for w in caught if issubclass(w.category, HalfOverflowWarning)]
    assert len(notes) == 1 and "24 value(s)" in str(notes[0].message)  # R and G: 2 x 12 pixels
    assert oiio_formats(tmp_path / "m.exr") == {"R": "half", "G": "half", "Z": "float"}
    got = oiio_pixels(tmp_path / "m.exr")
    assert (got["R"] == 65504).all() and (got["Z"] == 1e5).all()
