"""The Pixel's Ultra HDR photo of the shared corpus (formats/oiio-images/ultrahdr_sky.jpg, 4080 x 3072, Display P3
base, 1020 x 768 grey gain map): read as its HDR rendition, against the specification's formula transcribed in
float64 on Pillow's decoding of the base and of the gain map (found through Pillow's own MPF parser)."""

from __future__ import annotations

import io

import colour
import numpy as np
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
