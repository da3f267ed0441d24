"""The demo and the curve chart print no "the exposure has no effect" note: the user gave no exposure there.

`lenslab demo` printed that note three times for mantiuk, whose result does not depend on the exposure
(pfstmo's display mapping puts the scene's 0.1 to 99.9 percentiles on the display); the charts and the demo's
pages now give it none, and what they show is unchanged (mantiuk at exposure 0 equals mantiuk at +1.82 EV).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

pytest.importorskip("cv2")

from lenslab.tone.mapping import ExposureIgnoredWarning  # noqa: E402
from lenslab.tone.plot import curve_samples  # noqa: E402


def test_the_curve_chart_gives_mantiuk_no_exposure():
    with warnings.catch_warnings():
        warnings.simplefilter("error", ExposureIgnoredWarning)
        x, y = curve_samples("mantiuk", exposure=1.82)
    assert np.isfinite(y).all() and x.shape == y.shape


def test_the_gallery_tones_mantiuk_without_a_note_and_as_at_any_exposure():
    from gallery.display import tone
    from lenslab.tone import tonemap

    rng = np.random.default_rng(0)
    image = (rng.random((32, 48, 3)) ** 4 * 20).astype(np.float32)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ExposureIgnoredWarning)
        shown = tone(image, "mantiuk", exposure=1.82)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ExposureIgnoredWarning)
        at_exposure = np.clip(tonemap(image, curve="mantiuk", exposure=1.82), 0, 1)
    # 1e-5: the exposure multiplies float32 values before their log, which rounds differently (1.3e-6 measured)
    np.testing.assert_allclose(shown, at_exposure, rtol=0, atol=1e-5)
