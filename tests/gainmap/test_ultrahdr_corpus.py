"""The Pixel's Ultra HDR photo of the shared corpus (formats/oiio-images/ultrahdr_sky.jpg, 4080 x 3072, Display P3
base, 1020 x 768 grey gain map): read as its HDR rendition, against the specification's formula transcribed in
float64 on Pillow's decoding of the base and of the gain map (found through Pillow's own MPF parser)."""

from __future__ import annotations

import io

import colour
import numpy as np
import pytest
from PIL import Image, JpegImagePlugin

import lenslab.io as lio
from tests.gainmap.files import apply_formula, bilinear_at_centres, srgb_decode

STEP = 7  # every 7th row and column: 250k pixels compared, the float64 arrays kept small
#: the file's gain map XMP, as printed in it (hdrgm:GainMapMin 0, GainMapMax 2.205275, offsets 0, no Gamma: 1)
GAIN_MAP_MAX = 2.205275


def _pillow_parts(path):
    with Image.open(path) as im:
        base = np.asarray(im)
        entry = JpegImagePlugin._getmp(im)[0xB002][1]
        start = im.info["mpoffset"] + entry["DataOffset"]
    blob = path.read_bytes()[start:start + entry["Size"]]
    with Image.open(io.BytesIO(blob)) as g:
        return base, np.asarray(g)[..., None], g.info["xmp"]


def test_the_sky_reads_as_its_hdr_rendition(shared_data):
    path = shared_data / "formats/oiio-images/ultrahdr_sky.jpg"
    base, gain, xmp = _pillow_parts(path)
    assert base.shape == (3072, 4080, 3) and gain.shape == (768, 1020, 1)
    assert b'hdrgm:GainMapMax="2.205275"' in xmp and b'hdrgm:OffsetSDR="0.000000"' in xmp
    # Display P3 base: the sRGB curve, then P3-D65 -> Rec.709 primaries (colour-science), float64
    p3 = srgb_decode(base[::STEP, ::STEP] / 255.0)
    sdr = colour.RGB_to_RGB(p3, colour.RGB_COLOURSPACES["Display P3"], colour.RGB_COLOURSPACES["sRGB"])
    r = bilinear_at_centres(gain / 255.0, 3072, 4080, STEP)
    want = apply_formula(sdr, r, 0.0, GAIN_MAP_MAX, 1.0, 0.0, 0.0)
    ours, meta = lio.read(path)
    ours_sdr, _ = lio.read(f"{path}:sdr")
    got, got_sdr = ours[::STEP, ::STEP].astype(np.float64), ours_sdr[::STEP, ::STEP].astype(np.float64)
    # lenslab decodes the base by its ICC profile (D50 colorants and parametric curve in s15Fixed16), not by the
    # ideal P3 matrix: with zero offsets the HDR differs from the formula by that SDR difference times the gain,
    # plus float32 rounding (a few 6e-8 relative steps)
    bound = np.abs(got_sdr - sdr) * np.exp2(GAIN_MAP_MAX * r) + 1e-6 * np.abs(want) + 1e-7
    assert (np.abs(got - want) <= bound).mean() == 1.0, np.abs(got - want).max()
    assert np.abs(got_sdr - sdr).max() < 2e-3  # the two SDR decodes agree to a fraction of a code
    assert abs(ours.max() - 2 ** GAIN_MAP_MAX * ours_sdr.max()) < 0.05 * ours.max()  # white boosted 4.61x
    assert "headroom 2.21 stops" in meta["attributes"]["gain_map"]


def test_the_skys_gain_is_libultrahdrs_where_the_gain_map_is_flat(shared_data):
    """Google's libultrahdr (imagecodecs' ``ultrahdr_decode``) on the same photo. It samples the gain map at
    ``x * w / W`` (corners aligned), lenslab at the pixel centres: where a gain map pixel and its 8 neighbours
    hold one code, both sample that code. There the gains (HDR over SDR; the file's offsets are 0) agree within
    libultrahdr's float16 output (2^-11 relative for each of its HDR and SDR values) and one entry of its
    1024-entry gain table (GainMapMax / 1023 stops); its own Y'CbCr conversion of the base cancels in the ratio."""
    imagecodecs = pytest.importorskip("imagecodecs")
    if not imagecodecs.ULTRAHDR.available:
        pytest.skip("this imagecodecs was built without libultrahdr")
    path = shared_data / "formats/oiio-images/ultrahdr_sky.jpg"
    blob = path.read_bytes()
    hdr = imagecodecs.ultrahdr_decode(blob)[::STEP, ::STEP, :3].astype(np.float64)
    sdr = imagecodecs.ultrahdr_decode(blob, boost=1.0)[::STEP, ::STEP, :3].astype(np.float64)
    ours, _ = lio.read(path)
    ours_sdr, _ = lio.read(f"{path}:sdr")
    ours, ours_sdr = ours[::STEP, ::STEP], ours_sdr[::STEP, ::STEP]
    _, gain, _ = _pillow_parts(path)
    windows = np.lib.stride_tricks.sliding_window_view(np.pad(gain[..., 0], 1, mode="edge"), (3, 3))
    flat = windows.max(axis=(2, 3)) == windows.min(axis=(2, 3))
    rows, cols = np.arange(0, 3072, STEP) // 4, np.arange(0, 4080, STEP) // 4  # the gain map is 4x smaller
    keep = flat[rows][:, cols] & (sdr.min(axis=2) > 0.01) & (ours_sdr.min(axis=2) > 0.01)
    with np.errstate(divide="ignore", invalid="ignore"):
        diff = np.abs(np.log2(hdr / sdr) - np.log2(ours / ours_sdr))[keep]
    tolerance = 2 * np.log2(1 + 2.0 ** -11) + GAIN_MAP_MAX / 1023
    assert keep.mean() > 0.3 and diff.max() <= tolerance, (keep.mean(), diff.max())
