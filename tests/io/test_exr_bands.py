"""EXR's first part is read a band of whole chunks at a time into the float32 image
(lenslab.io.exr.bands): the values are those OpenImageIO reads (its own EXR reader, float, the data
window), bit for bit, for every compression's chunk height (1, 16, 32 and 256 scanlines), tiles, a data
window inside and across the display window, decreasing line order and half, float and uint channels
(uint as OpenEXR's own reader gives it, since OpenImageIO scales integers to [0, 1]). Bands of one chunk
each (BAND_BYTES forced small) and of the usual size give the same image."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.exr import bands

oiio = pytest.importorskip("OpenImageIO")

H, W = 203, 77


def _oiio(path) -> tuple[np.ndarray, tuple[int, int]]:
    """The data window's pixels as OpenImageIO reads them (float), and its origin."""
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    return pixels.reshape(spec.height, spec.width, spec.nchannels), (spec.x, spec.y)


def _write(path, channels, compression="ZIP", tiled=False, data=((0, 0), (W - 1, H - 1)),
           display=((0, 0), (W - 1, H - 1)), order="INCREASING_Y"):
    header = {"compression": getattr(OpenEXR, f"{compression}_COMPRESSION"), "dataWindow": data,
              "displayWindow": display, "lineOrder": getattr(OpenEXR, order),
              "type": OpenEXR.tiledimage if tiled else OpenEXR.scanlineimage}
    if tiled:
        tiles = OpenEXR.TileDescription()
        tiles.xSize, tiles.ySize, tiles.mode = 32, 24, OpenEXR.ONE_LEVEL
        header["tiles"] = tiles
    OpenEXR.File(header, channels).write(str(path))


def _rgba(seed=0, dtype=np.float16):
    rng = np.random.default_rng(seed)
    img = (rng.standard_normal((H, W, 4)) * 10.0 ** rng.uniform(-3, 3, (H, W, 4))).astype(dtype)
    img.flat[:4] = [np.inf, -np.inf, np.nan, 0.0]
    return {c: np.ascontiguousarray(img[..., i]) for i, c in enumerate("RGBA")}


@pytest.fixture(params=["one chunk", "usual"])
def band_size(request, monkeypatch):
    """Bands of one chunk or of the usual size; the test's reads must take the band reader."""
    if request.param == "one chunk":
        monkeypatch.setattr(bands, "BAND_BYTES", 1)
    calls = []
    read_into = bands.read_into
    monkeypatch.setattr(bands, "read_into", lambda *a, **k: calls.append(1) or read_into(*a, **k))
    yield request.param
    assert calls, "the image was not read by bands"


@pytest.mark.parametrize("compression", ["NO", "ZIP", "PIZ", "DWAB"])
@pytest.mark.parametrize("tiled", [False, True])
def test_bands_read_what_openimageio_reads(tmp_path, band_size, compression, tiled):
    path = tmp_path / "b.exr"
    _write(path, _rgba(), compression, tiled, order="DECREASING_Y" if compression == "PIZ" and not tiled else
           "INCREASING_Y")
    image, meta = lio.read(path)
    expected, _ = _oiio(path)
    assert image.shape == (H, W, 4) and meta["sample_type"] == "half"
    assert np.array_equal(image.view(np.uint32), expected.astype(np.float32).view(np.uint32))


@pytest.mark.parametrize("data", [((5, 9), (W - 8, H - 30)), ((-6, -11), (W + 3, H + 17))])
def test_a_data_window_is_placed_in_the_display_window(tmp_path, band_size, data):
    (x0, y0), (x1, y1) = data
    w, h = x1 - x0 + 1, y1 - y0 + 1
    rng = np.random.default_rng(3)
    chans = {c: rng.random((h, w), dtype=np.float32) for c in "RGB"}
    path = tmp_path / "w.exr"
    _write(path, chans, "PIZ", data=data)
    pixels, origin = _oiio(path)
    assert origin == (x0, y0)
    kept, _ = lio.read(path, data_window=True)
    assert np.array_equal(kept, pixels)
    placed, _ = lio.read(path)
    expected = np.zeros((H, W, 3), np.float32)
    ix0, iy0, ix1, iy1 = max(x0, 0), max(y0, 0), min(x1, W - 1), min(y1, H - 1)
    expected[iy0:iy1 + 1, ix0:ix1 + 1] = pixels[iy0 - y0:iy1 - y0 + 1, ix0 - x0:ix1 - x0 + 1]
    assert np.array_equal(placed, expected)


def test_half_float_and_uint_channels_keep_their_values(tmp_path, band_size):
    rng = np.random.default_rng(5)
    chans = {"R": rng.random((H, W), dtype=np.float32).astype(np.float16),
             "G": rng.standard_normal((H, W)).astype(np.float32) * 1e20,
             "B": rng.integers(0, 2 ** 32, (H, W), dtype=np.uint32)}
    path = tmp_path / "t.exr"
    _write(path, chans, "ZIP")
    image, meta = lio.read(path)
    expected, _ = _oiio(path)
    assert np.array_equal(image[..., :2], expected[..., :2])
    own = OpenEXR.File(str(path), separate_channels=True).channels()["B"].pixels  # OpenEXR's own reader
    assert np.array_equal(image[..., 2], own.astype(np.float32))
    assert meta["sample_type"] == "float/half/uint" and meta["bit_depth"] == 32


def test_other_primaries_are_converted_in_every_band(tmp_path, band_size):
    """Rec.2020 primaries (the file's chromaticities attribute) to Rec.709 over 600 rows (several bands
    of the conversion): colour-science's RGB_to_RGB matrix in float64 (both white points D65, no
    adaptation), within float32's rounding of a 3 x 3 product (1e-6 of values up to 1.7)."""
    colour = pytest.importorskip("colour")
    rng = np.random.default_rng(6)
    img = rng.random((600, 40, 3)).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "chromaticities": (0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290)}
    path = tmp_path / "p.exr"
    OpenEXR.File(header, {"RGB": img}).write(str(path))
    image, meta = lio.read(path)
    m = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"], colour.RGB_COLOURSPACES["ITU-R BT.709"],
                                 chromatic_adaptation_transform=None)
    assert meta["primaries_converted_to_rec709"]
    np.testing.assert_allclose(image, img.astype(np.float64) @ m.T, rtol=0, atol=1e-6)
