"""The tone-curve chart as a library function: a matplotlib Figure drawing what the curves compute."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import tone
from lenslab.errors import ToneError
from lenslab.tone.plot import curve_samples, plot_curves


def test_plot_curves_draws_every_curve_on_both_panels():
    from matplotlib.figure import Figure

    fig = plot_curves()
    assert isinstance(fig, Figure)
    enc, lin = fig.axes[:2]
    labels = [line.get_label() for line in lin.get_lines() if not line.get_label().startswith("_")]
    assert labels == list(tone.CURVES)
    # the right panel holds the display-linear output itself: hable's line is tonemap's result
    hable = next(line for line in lin.get_lines() if line.get_label() == "hable")
    x, y = hable.get_data()
    np.testing.assert_array_equal(y, tone.tonemap(np.asarray(x, np.float32), "hable"))
    assert x[0] == pytest.approx(2.0 ** -10) and x[-1] == pytest.approx(2.0 ** 8)


def test_plot_curves_subset_stops_and_exposure():
    fig = plot_curves(["aces", "Reinhard"], stops=(-4, 2), exposure=1.5)
    lin = fig.axes[1]
    lines = {line.get_label(): line for line in lin.get_lines() if not line.get_label().startswith("_")}
    assert set(lines) == {"aces", "reinhard"}
    x, y = lines["reinhard"].get_data()
    assert x[0] == pytest.approx(2.0 ** -4) and x[-1] == pytest.approx(2.0 ** 2)
    s = 2.0 ** 1.5 * np.asarray(x, np.float64)
    np.testing.assert_allclose(y, s / (1 + s), rtol=1e-5)  # float32 curve, a few ulps
    assert "+1.5" in fig.get_suptitle()
    assert set(l.get_label() for l in plot_curves("hable,agx").axes[1].get_lines()) >= {"hable", "agx"}


def test_plot_curves_rejects_bad_names_and_ranges():
    with pytest.raises(ToneError, match="valid curves"):
        plot_curves(["hable", "velvia"])
    with pytest.raises(ToneError, match="LOW < HIGH"):
        plot_curves(stops=(3, 1))


def test_curve_samples_for_image_and_local_curves():
    x, y = curve_samples("reinhard2002", (-6, 6), n=64)
    np.testing.assert_allclose(y, x / (1 + x), rtol=1e-5)  # log-average at middle grey: key 0.18 cancels
    x, y = curve_samples("drago", (-6, 6), n=64)
    assert x.shape == y.shape == (64,) and np.all(np.diff(y) >= -1e-6) and y.max() <= 1
