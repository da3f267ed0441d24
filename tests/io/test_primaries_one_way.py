"""Other primaries become Rec.709 one way (:func:`lenslab.io.colour.primaries.to_rec709`, a band of rows at a time,
in place) for an EXR's ``chromaticities`` attribute and a PNG's cICP primaries alike. Expected values:
colour-science's ``RGB_to_RGB`` in float64 on the same pixels (no chromatic adaptation for the EXR: its
XYZ unchanged, as OpenEXR's RGB -> XYZ of its chromaticities gives it), the pixels read by OpenEXR."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.colour import primaries

colour = pytest.importorskip("colour")

# ACES AP0 and its D60 white: primaries and a white far from Rec.709's (x, y of R, G, B, white)
AP0 = (0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.077, 0.32168, 0.33767)
BT709 = colour.RGB_COLOURSPACES["ITU-R BT.709"]


def _bound(matrix, rgb):
    """float32 rounding of a 3-term product sum and of the matrix: 8 ulp of the largest partial sum."""
    return 8 * np.finfo(np.float32).eps * (np.abs(rgb.astype(np.float64)) @ np.abs(matrix).T) + 1e-30


@pytest.fixture
def applied(monkeypatch):
    calls = []
    real = primaries.to_rec709
    monkeypatch.setattr(primaries, "to_rec709", lambda image, m, *a: calls.append(np.array(m)) or real(image, m, *a))
    return calls


def test_an_exr_with_ap0_chromaticities_is_read_as_colour_science_converts_it(tmp_path, applied):
    rng = np.random.default_rng(4)
    h, w = 300, 7  # more rows than a band: the band edges hold too
    rgba = np.concatenate([rng.uniform(0, 20, (h, w, 3)), rng.uniform(0, 1, (h, w, 1))], -1).astype(np.float32)
    path = tmp_path / "ap0.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "chromaticities": AP0}
    OpenEXR.File(header, {"RGBA": rgba}).write(str(path))
    image, meta = lio.read(path)
    assert meta["primaries_converted_to_rec709"] and len(applied) == 1
    stored = OpenEXR.File(str(path)).parts[0].channels["RGBA"].pixels.astype(np.float64)
    chroma = np.asarray(OpenEXR.File(str(path), header_only=True).parts[0].header["chromaticities"], np.float64)
    space = colour.RGB_Colourspace("AP0", chroma[:6].reshape(3, 2), chroma[6:], use_derived_matrix_RGB_to_XYZ=True,
                                   use_derived_matrix_XYZ_to_RGB=True)
    expected = colour.RGB_to_RGB(stored[..., :3], space, BT709, chromatic_adaptation_transform=None)
    m = colour.matrix_RGB_to_RGB(space, BT709, None)
    assert np.all(np.abs(image[..., :3] - expected) <= _bound(m, stored[..., :3]))
    np.testing.assert_array_equal(image[..., 3], stored[..., 3])  # alpha untouched


def test_a_p3_png_goes_through_the_same_function_as_colour_science_converts_it(tmp_path, applied):
    from lenslab.io.colour.png_cicp import wide_to_709

    rng = np.random.default_rng(5)
    linear = rng.uniform(0, 1, (260, 5, 4)).astype(np.float32)
    got = linear.copy()
    note = wide_to_709(got, 12)
    assert "P3-D65" in note and len(applied) == 1
    expected = colour.RGB_to_RGB(linear[..., :3].astype(np.float64), colour.RGB_COLOURSPACES["P3-D65"], BT709)
    m = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["P3-D65"], BT709)
    assert np.all(np.abs(got[..., :3] - expected) <= _bound(m, linear[..., :3]))
    np.testing.assert_array_equal(got[..., 3], linear[..., 3])


def test_a_tagged_png_file_is_read_through_it(tmp_path, applied):
    from lenslab.io.colour.png_cicp import with_cicp

    codes = np.random.default_rng(6).uniform(0, 1, (6, 9, 3)).astype(np.float32)
    plain = tmp_path / "plain.png"
    lio.write(plain, codes, raw=True, bits=16)
    tagged = tmp_path / "p3.png"
    tagged.write_bytes(with_cicp(plain.read_bytes(), (12, 13, 0, 1)))
    image, _ = lio.read(tagged)
    decoded, _ = lio.read(plain)  # the same sRGB decoding, untagged: Rec.709 as it is
    assert len(applied) == 1
    expected = colour.RGB_to_RGB(decoded.astype(np.float64), colour.RGB_COLOURSPACES["P3-D65"], BT709)
    m = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["P3-D65"], BT709)
    assert np.all(np.abs(image - expected) <= _bound(m, decoded))


def test_a_pq_png_on_bt2020_goes_through_it_as_colour_science_decodes_it(tmp_path, applied):
    from lenslab.io.colour.png_cicp import with_cicp

    codes = np.random.default_rng(7).integers(0, 65536, (5, 8, 3)).astype(np.float32) / 65535
    plain = tmp_path / "plain.png"
    lio.write(plain, codes, raw=True, bits=16)
    tagged = tmp_path / "pq.png"
    tagged.write_bytes(with_cicp(plain.read_bytes(), (9, 16, 0, 1)))  # Rec.2100 PQ: BT.2020, ST 2084
    image, _ = lio.read(tagged)
    assert len(applied) == 1
    stored, _ = lio.read(plain, raw=True)  # the 16-bit codes / 65535, as written
    stored = np.round(stored.astype(np.float64) * 65535) / 65535  # each code's value exact, in float64
    light = colour.eotf(stored, "ST 2084") / 203.0  # 1.0 = 203 cd/m2 (ITU-R BT.2408)
    expected = colour.RGB_to_RGB(light, colour.RGB_COLOURSPACES["ITU-R BT.2020"], BT709)
    # float64 throughout, rounded once to float32 at the end: 2 ulp of float32, plus 1e-9 for the
    # two float64 evaluations of the PQ curve (a 10000 cd/m2 code is 49 times the reference white)
    np.testing.assert_allclose(image, expected, rtol=2 * np.finfo(np.float32).eps, atol=1e-9)
