"""The engine's note on non-finite outputs says what happened: NaN or inf in the source (counted), or a
finite source whose values passed float32's range in the warp's arithmetic (the outputs counted and
clamped), never "0 non-finite values". Expected values: lensfun's pa falloff ``1 + k1 r^2`` in float64."""

from __future__ import annotations

import re
import warnings

import numpy as np

from lenslab.lenses import Camera
from lenslab.warp import warp

BIG = float(np.finfo(np.float32).max)
K1 = -0.3


def _warp(img, src, dst):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out, cover = warp(img, src, dst)
    return out, cover, [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]


def test_a_finite_source_that_overflows_in_the_vignetting_is_said_so():
    src = Camera.from_spec(f"optics:vignetting=pa/{K1}/0/0,base=perspective,fov=60", (40, 30))
    dst = Camera.from_spec("perspective:fov=60", (40, 30))  # the same rays: read at the pixel centres
    value = 3.0e38
    out, _, notes = _warp(np.full((30, 40, 3), value, np.float32), src, dst)
    assert len(notes) == 1
    note = notes[0]
    assert "the source is finite" in note and "0 non-finite" not in note and "source has" not in note
    n = int(re.search(r"but (\d+) output values", note).group(1))
    assert np.isfinite(out).all()
    y, x = np.mgrid[0:30, 0:40] + 0.5
    f = 1.0 + K1 * (np.hypot(x - 20, y - 15) / (0.5 * np.hypot(40, 30))) ** 2
    want = value / f  # float64: the light the vignetting removal asks for
    far_out, far_in = want > 1.01 * BIG, want < 0.99 * BIG
    assert far_out.any() and far_in.any()
    assert np.all(out[far_out] == np.float32(BIG))  # clamped to the largest float32
    np.testing.assert_allclose(out[far_in], np.repeat(want[far_in][:, None], 3, 1), rtol=1e-4)
    assert n == int(np.count_nonzero(out == np.float32(BIG)))  # the count said is the count clamped


def test_a_source_with_nan_is_counted():
    src, dst = Camera.from_spec("equirect", (16, 8)), Camera.from_spec("equirect", (32, 16))
    img = np.ones((8, 16, 3), np.float32)
    img[3, 5, 1] = np.nan
    img[4, 9, 0] = np.inf
    out, _, notes = _warp(img, src, dst)
    assert notes == ["the source has 2 non-finite values: NaN read as 0, +-inf as the largest float32"]
    assert np.isfinite(out).all()
