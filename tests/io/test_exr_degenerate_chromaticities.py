"""An EXR whose ``chromaticities`` attribute describes no colour space (two primaries at one point, a white
with y = 0 or outside the primaries' triangle, numbers that are not finite) is refused in one line before its
primaries are converted to Rec.709, instead of giving numbers from a singular or nearly singular matrix
(colour-science's own answer for such a header: a "Singular matrix" error, or values scaled by 1e8).
Every colour space colour-science publishes (ACES AP0, whose blue has a negative y, included) still reads,
converted by colour-science's matrix."""

from __future__ import annotations

import math

import colour
import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.errors import FormatError

RGB = np.array([0.25, 0.5, 0.125], np.float32)


def _write(path, chroma):
    img = np.broadcast_to(RGB, (4, 6, 3)).copy()
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
                  "chromaticities": tuple(float(v) for v in chroma)}, {"RGB": img}).write(str(path))
    return path


DEGENERATE = {
    "red on green": (0.64, 0.33, 0.64, 0.33, 0.15, 0.06, 0.3127, 0.3290),
    "primaries on a line": (0.6, 0.3, 0.4, 0.3, 0.2, 0.3, 0.3127, 0.3),
    "white with y = 0": (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.0),
    "white near y = 0": (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 1e-30),
    "white outside": (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.9, 0.05),
    "huge": (1e30,) * 8,
    "not a number": (math.nan,) * 8,
    "infinite white": (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, math.inf, 0.3290),
}


@pytest.mark.parametrize("name", list(DEGENERATE))
def test_a_header_that_is_no_colour_space_is_refused_in_one_line(tmp_path, name):
    path = _write(tmp_path / "bad.exr", DEGENERATE[name])
    with pytest.raises(FormatError) as err:
        lio.read(path)
    message = str(err.value)
    assert "\n" not in message and "chromaticities" in message and str(path) in message
    image, _ = lio.read(path, rec709=False)  # the file's own numbers, unconverted, still read
    np.testing.assert_array_equal(image[0, 0], RGB)


def test_every_published_colour_space_converts_by_colour_sciences_matrix(tmp_path):
    rec709 = colour.RGB_COLOURSPACES["ITU-R BT.709"]
    checked = 0
    for name, space in colour.RGB_COLOURSPACES.items():
        chroma = np.concatenate([np.asarray(space.primaries, np.float64).reshape(-1),
                                 np.asarray(space.whitepoint, np.float64).reshape(-1)])
        if np.allclose(chroma, [0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290], atol=1e-4):
            continue
        path = _write(tmp_path / "space.exr", chroma)
        image, meta = lio.read(path)
        # colour-science's conversion of the stored (float32) chromaticities, without adaptation, in float64
        stored = np.asarray(OpenEXR.File(str(path), header_only=True).parts[0].header["chromaticities"],
                            np.float64).reshape(-1)
        file_space = colour.RGB_Colourspace("file", stored[:6].reshape(3, 2), stored[6:8],
                                            use_derived_matrix_RGB_to_XYZ=True, use_derived_matrix_XYZ_to_RGB=True)
        want = colour.RGB_to_RGB(RGB.astype(np.float64), file_space, rec709, None)
        assert meta["primaries_converted_to_rec709"], name
        # float32 arithmetic of a 3 x 3 product of values below 2: within 1e-6
        np.testing.assert_allclose(image[0, 0], want, rtol=0, atol=1e-6, err_msg=name)
        checked += 1
    assert checked > 30
