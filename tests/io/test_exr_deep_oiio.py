"""The deep Trunks files (``v2/LowResLeftView/Trunks.exr``: deep scanline, RGBA half + Z float, data window
offset; ``v2/Stereo/Trunks.exr``: two deep parts, rgba.left and rgba.right) read flattened, against
OpenImageIO's ``ImageBufAlgo.flatten`` of the same part.

OpenImageIO composites each pixel's samples with "over" in float32, stopping at an opaque sum, in the order
the file stores them (3.2.2 does not sort them; the Trunks files store every pixel front to back, which the
fixture checks, so that order is depth order here); it does not merge samples at the same depth, which
OpenEXR's "Interpreting OpenEXR Deep Pixels" requires before flattening (its "Merging Overlapping Samples"). So: pixels without two samples at one depth
must equal OpenImageIO's; pixels with such samples are checked against that merge formula, transcribed here
in float64 from the document, followed by "over".

Tolerance: the samples are half floats (exact in float32 and float64); OpenImageIO's float32 over of two
samples and lenslab's float64 one rounded to float32 differ by at most a few float32 ulps of values <= 1:
``2**-21``. (They agree exactly on these files.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import lenslab.io as lio

oiio = pytest.importorskip("OpenImageIO")
OpenEXR = pytest.importorskip("OpenEXR")

ULPS = 2.0 ** -21
CASES = [("LowResLeftView", 0), ("Stereo", 0), ("Stereo", 1)]


def merged(a1, c1, a2, c2):
    """The document's merge of two coinciding samples (alpha, colour), float64, as its example code
    computes it."""
    am = a1 + a2 - a1 * a2
    if a1 == 1 and a2 == 1:
        return am, (c1 + c2) / 2
    if a1 == 1:
        return am, c1
    if a2 == 1:
        return am, c2
    u1 = -math.log1p(-a1) if a1 > 0 else 0.0
    u2 = -math.log1p(-a2) if a2 > 0 else 0.0
    v1 = u1 / a1 if a1 > 0 else 1.0
    v2 = u2 / a2 if a2 > 0 else 1.0
    w = am / (u1 + u2) if u1 + u2 != 0 else 1.0
    return am, w * (c1 * v1 + c2 * v2)


def over_tidy(zs, alphas, colours):
    """Sorted by Z, samples at one depth merged (left to right), then composited front to back."""
    order = sorted(range(len(zs)), key=lambda i: zs[i])
    layers = []
    for i in order:
        if layers and layers[-1][0] == zs[i]:
            a, c = layers[-1][1], layers[-1][2]
            merged_c = [merged(a, c[k], alphas[i], colours[i][k])[1] for k in range(len(c))]
            layers[-1] = (zs[i], merged(a, 0.0, alphas[i], 0.0)[0], merged_c)
        else:
            layers.append((zs[i], float(alphas[i]), [float(v) for v in colours[i]]))
    out_a, out_c = 0.0, [0.0] * len(colours[0])
    for _, a, c in layers:
        if out_a >= 1:
            break
        out_c = [oc + (1 - out_a) * v for oc, v in zip(out_c, c)]
        out_a = out_a + (1 - out_a) * a
    return out_a, out_c


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c[0]}-part{c[1]}")
def case(request, shared_data):
    folder, part = request.param
    path = shared_data / "formats" / "openexr-images" / "v2" / folder / "Trunks.exr"
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the note that the first of two parts is read
        image, meta = lio.read(f"{path}:{part}", data_window=True)
    flat = oiio.ImageBufAlgo.flatten(oiio.ImageBuf(str(path), part, 0))
    assert not flat.has_error, flat.geterror()
    names = list(flat.spec().channelnames)
    pixels = flat.get_pixels(oiio.FLOAT)
    ref = np.stack([pixels[..., names.index(c)] for c in "RGBA"], -1)
    samples = OpenEXR.File(str(path)).parts[part].channels
    z = samples["Z"].pixels
    tied = np.zeros(z.shape, bool)
    for (y, x), zz in np.ndenumerate(z):
        if zz is not None and len(np.unique(zz)) < len(zz):
            tied[y, x] = True
        assert zz is None or (np.diff(zz) >= 0).all()  # stored front to back: OpenImageIO's order is depth order
    return path, part, image, meta, ref, samples, tied


def test_the_flat_image_is_openimageio_s_flatten_where_no_samples_coincide(case):
    path, part, image, meta, ref, _, tied = case
    assert meta["channels"] == ["R", "G", "B", "A"] and meta["part"] == part
    assert image.shape == ref.shape and meta["data_window"] == [0, 141 if "LowRes" in str(path) else 266,
                                                                image.shape[1] - 1, 575 if "LowRes" in str(path)
                                                                else 1079]
    assert (~tied).sum() > 400_000
    np.testing.assert_allclose(image[~tied], ref[~tied], rtol=0, atol=ULPS)
    assert image[..., 3].max() == 1 and image[..., 3].min() == 0  # opaque and empty pixels both present


def test_coinciding_samples_merge_as_the_deep_pixels_document_says(case):
    _, _, image, _, ref, samples, tied = case
    assert tied.sum() >= 30  # the files hold such pixels: 33, 172 and more
    rgba = samples["RGBA"].pixels
    z = samples["Z"].pixels
    far = 0
    for y, x in zip(*np.nonzero(tied)):
        s = rgba[y, x].astype(np.float64)
        a, c = over_tidy(list(z[y, x]), s[:, 3], s[:, :3])
        np.testing.assert_allclose(image[y, x], [*c, a], rtol=0, atol=ULPS)
        far = max(far, float(np.abs(image[y, x] - ref[y, x]).max()))
    assert far > 1e-3  # where OpenImageIO composites such samples one over the other, it differs


def test_the_display_window_read_places_the_data_window(case):
    path, part, image, _, _, _, _ = case
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full, meta = lio.read(f"{path}:{part}")
    x0, y0, x1, y1 = meta["data_window"]
    assert full.shape[:2] == ((1080, 1920) if "Stereo" in str(path) else (576, 1024))
    np.testing.assert_array_equal(full[y0:y1 + 1, x0:x1 + 1], image)
    assert not full[:y0].any()
