"""EXR specifics: parts, layers, data/display windows, luminance-chroma maths, pixel types."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.exr import REC709, luminance_weights, upsample, yca_to_rgb


def _win(x0, y0, x1, y1):
    return (np.array([x0, y0], np.int32), np.array([x1, y1], np.int32))


def _multipart(path):
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    a = np.full((4, 5), 1.0, np.float32)
    layers = {
        "beauty": {"R": a, "G": 2 * a, "B": 3 * a},
        "depth": {"Z": 7 * a},
        "stereo": {"R": 4 * a, "G": 5 * a, "B": 6 * a, "left.R": 8 * a, "left.G": 9 * a, "left.B": 10 * a},
    }
    parts = [OpenEXR.Part({**h, "name": name}, chans, name) for name, chans in layers.items()]
    OpenEXR.File(parts).write(str(path))
    return path


def test_multipart_selection_by_index_name_and_layer(tmp_path):
    p = _multipart(tmp_path / "m.exr")
    img, meta = lio.read(p)
    assert img[0, 0].tolist() == [1, 2, 3] and meta["part"] == 0 and meta["parts"] == ["beauty", "depth", "stereo"]
    img, meta = lio.read(f"{p}:1")
    assert img.shape == (4, 5, 1) and img[0, 0, 0] == 7 and meta["channels"] == ["Z"]
    img, meta = lio.read(f"{p}:depth")
    assert img[0, 0, 0] == 7 and meta["part_name"] == "depth"
    img, _ = lio.read(f"{p}:stereo")
    assert img[0, 0].tolist() == [4, 5, 6]
    img, meta = lio.read(f"{p}:stereo:left")
    assert img[0, 0].tolist() == [8, 9, 10] and meta["layer"] == "left"
    img, meta = lio.read(f"{p}:left")  # a lone layer name finds the part that has it
    assert img[0, 0].tolist() == [8, 9, 10] and meta["part"] == 2
    with pytest.raises(lio.FormatError, match="part 5 does not exist.*3 part"):
        lio.read(f"{p}:5")
    with pytest.raises(lio.FormatError, match="no part, layer or view named 'right'.*layers: left"):
        lio.read(f"{p}:right")


def test_data_window_placed_in_display_window(tmp_path):
    y = np.arange(24, dtype=np.float32).reshape(4, 6) + 1
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
         "dataWindow": _win(2, 1, 7, 4), "displayWindow": _win(-1, 0, 8, 5)}
    OpenEXR.File(h, {"R": y, "G": y, "B": y, "A": np.ones_like(y)}).write(str(tmp_path / "dw.exr"))
    img, meta = lio.read(tmp_path / "dw.exr")
    assert img.shape == (6, 10, 4)
    np.testing.assert_array_equal(img[1:5, 3:9, 0], y)  # data (2..7, 1..4) at display offset (-1, 0)
    inside = np.zeros((6, 10), bool)
    inside[1:5, 3:9] = True
    assert np.all(img[~inside] == 0)  # outside the data window: colour 0 and alpha 0
    assert np.all(img[inside][:, 3] == 1)
    kept, meta = lio.read(tmp_path / "dw.exr", data_window=True)
    np.testing.assert_array_equal(kept[..., 0], y)
    assert meta["origin"] == [2, 1] and meta["display_window"] == [-1, 0, 8, 5]


def test_upsample_is_linear_between_samples():
    # chroma linear in x and y, sampled at even coordinates: interpolation is exact in between
    w, h = 33, 17
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    full = 0.25 * xx - 0.5 * yy + 3.0
    sub = full[::2, ::2]
    np.testing.assert_allclose(upsample(sub, 2, 2, w, h, 0, 0), full, atol=1e-5)  # float32 rounding
    # a data window from (1, 1) to (31, 15): samples sit at even absolute coordinates 2, 4, ..., 30,
    # i.e. local 1, 3, ...; the first and last pixels lie outside the samples and take the nearest one
    out = upsample(full[2:-1:2, 2:-1:2], 2, 2, w - 2, h - 2, 1, 1)
    np.testing.assert_allclose(out[1:-1, 1:-1], full[2:-2, 2:-2], atol=1e-5)
    np.testing.assert_allclose(out[0, 1:-1], full[2, 2:-2], atol=1e-5)


def test_yca_to_rgb_inverts_the_encoding():
    rng = np.random.default_rng(0)
    rgb = rng.random((8, 9, 3)).astype(np.float32) + 0.05
    for chroma in (REC709, (0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.077, 0.32168, 0.33767)):
        wts = luminance_weights(chroma)
        assert abs(wts.sum() - 1.0) < 1e-9  # white (1, 1, 1) has luminance 1
        y = rgb @ wts.astype(np.float32)
        ry, by = (rgb[..., 0] - y) / y, (rgb[..., 2] - y) / y
        np.testing.assert_allclose(yca_to_rgb(y, ry, by, wts), rgb, rtol=1e-5)  # float32 arithmetic
    np.testing.assert_allclose(luminance_weights(REC709), [0.2126, 0.7152, 0.0722], atol=1e-4)  # Rec.709 Y


def test_uint_and_single_channels(tmp_path):
    ids = np.arange(20, dtype=np.uint32).reshape(4, 5) * 1000
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"id": ids}).write(str(tmp_path / "u.exr"))
    img, meta = lio.read(tmp_path / "u.exr")
    np.testing.assert_array_equal(img[..., 0], ids.astype(np.float32))
    assert meta["channels"] == ["id"] and meta["sample_type"] == "uint" and meta["bit_depth"] == 32


def test_grey_and_custom_channels_written(tmp_path):
    grey = np.random.default_rng(1).random((6, 7, 1)).astype(np.float32)
    f = OpenEXR.File(str(lio.write(tmp_path / "y.exr", grey, pixel_type="float")), separate_channels=True)
    assert list(f.channels()) == ["Y"]
    two = np.random.default_rng(2).random((6, 7, 2)).astype(np.float32)
    lio.write(tmp_path / "uv.exr", two, channels=["u", "v"], pixel_type="float")
    back, meta = lio.read(tmp_path / "uv.exr")
    np.testing.assert_array_equal(back, two)
    assert meta["channels"] == ["u", "v"]


def test_string_attributes_round_trip(tmp_path):
    lio.write(tmp_path / "a.exr", np.zeros((2, 3, 3), np.float32), attributes={"owner": "lenslab test"})
    _, meta = lio.read(tmp_path / "a.exr")
    assert meta["attributes"]["owner"] == "lenslab test"
    assert OpenEXR.File(str(tmp_path / "a.exr"), header_only=True).header()["owner"] == "lenslab test"
