"""Auto exposure of an image with alpha measures what a compositor shows: the covered pixels' straight
colour (premultiplied colour / alpha), each counted by its coverage. Expected values: the log-average
luminance ``2 ** (sum(a log2 L) / sum(a))`` transcribed in float64 here, with IEC 61966-2-1's luminance
weights, and NumPy's weighted percentile (``inverted_cdf``) for the trim."""

from __future__ import annotations

import re

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main
from lenslab.tone import auto_exposure, tonemap

Y709 = np.array([0.2126, 0.7152, 0.0722])  # IEC 61966-2-1, the Y row of sRGB's RGB -> XYZ


def _panorama_edge(seed=0):
    """A panorama whose right part is not covered: covered columns, a soft edge of alpha 7/8 .. 1/8, then
    nothing (one pixel of premultiplied glow with alpha 0: light, no coverage). Straight colours over
    ten stops; returned premultiplied (memory's convention) with the straight colour and alpha."""
    rng = np.random.default_rng(seed)
    h, w = 16, 64
    straight = np.exp2(rng.uniform(-5, 5, (h, w, 3)))
    alpha = np.zeros((h, w))
    alpha[:, :40] = 1.0
    alpha[:, 40:48] = np.linspace(7 / 8, 1 / 8, 8)[None, :]
    img = np.concatenate([straight * alpha[..., None], alpha[..., None]], axis=-1).astype(np.float32)
    img[3, 60, :3] = 0.5  # glow: alpha 0
    return img, straight, alpha


def _expected_ev(img, trim):
    """log2(0.18 / log-average), the log-average over covered pixels counted by coverage, in float64."""
    a = img[..., 3].astype(np.float64)
    covered = a > 0
    lum = (img[..., :3].astype(np.float64)[covered] / a[covered, None]) @ Y709
    logs, w = np.log2(lum), a[covered]
    if trim:
        lo, hi = np.percentile(logs, [trim, 100 - trim], weights=w, method="inverted_cdf")
        keep = (logs >= lo) & (logs <= hi)
        logs, w = logs[keep], w[keep]
    return float(np.log2(0.18 / 2.0 ** (np.sum(w * logs) / np.sum(w))))


def test_coverage_weighted_straight_colour():
    img, _, _ = _panorama_edge()
    # float32 input (colour and alpha rounded to 2**-24 relative) and float32 weights: 1e-6 stops
    assert auto_exposure(img, trim=0) == pytest.approx(_expected_ev(img, 0), abs=1e-6)
    assert auto_exposure(img) == pytest.approx(_expected_ev(img, 1.0), abs=1e-6)


def test_differs_from_premultiplied_colour():
    img, _, _ = _panorama_edge()
    premultiplied = auto_exposure(img[..., :3], trim=0)  # the colour over black, as the command measured it
    # the edge is an eighth of the covered pixels and darker by up to 3 stops premultiplied: a fifth of a stop
    assert abs(auto_exposure(img, trim=0) - premultiplied) > 0.1


def test_a_barely_covered_pixel_counts_by_its_coverage():
    # one covered grey pixel of 1.0, one covered 1/64 with a straight colour of 16 (premultiplied 0.25)
    img = np.array([[[1.0, 1.0, 1.0, 1.0], [0.25, 0.25, 0.25, 1 / 64]]], np.float32)
    log_avg = 2.0 ** ((1.0 * 0.0 + (1 / 64) * 4.0) / (1.0 + 1 / 64))  # log2 1 = 0, log2 16 = 4
    assert auto_exposure(img, trim=0) == pytest.approx(np.log2(0.18 / log_avg), abs=1e-6)  # float32 weights
    # as a whole pixel it would move the exposure by two stops
    assert np.log2(0.18 / 4.0) == pytest.approx(auto_exposure(img[..., :3] / img[..., 3:], trim=0), abs=1e-6)


def test_fully_covered_image_is_unchanged_by_alpha():
    img, straight, _ = _panorama_edge()
    full = np.concatenate([straight, np.ones(straight.shape[:2] + (1,))], axis=-1).astype(np.float32)
    assert auto_exposure(full) == pytest.approx(auto_exposure(full[..., :3]), abs=1e-12)


def test_tonemap_auto_uses_the_same_exposure():
    img, _, _ = _panorama_edge()
    ev = _expected_ev(img, 1.0)
    out = tonemap(img, "clamp", exposure="auto")
    a = img[..., 3:].astype(np.float64)
    straight = np.divide(img[..., :3], a, out=np.zeros(img[..., :3].shape), where=a > 0)
    expected = np.minimum(straight * 2.0 ** ev, 1.0) * a  # clamp of the exposed straight colour, premultiplied
    np.testing.assert_allclose(out[..., :3], expected, rtol=0, atol=2e-6)  # float32 of values below 1


def test_command_prints_the_coverage_weighted_exposure(tmp_path, capsys):
    img, _, _ = _panorama_edge()
    src = tmp_path / "edge.exr"
    lio.write(src, img, pixel_type="float")
    assert main(["tonemap", str(src), "-o", str(tmp_path / "edge.png"), "--exposure", "auto"]) == 0
    said = re.search(r"auto exposure ([+-]\d+\.\d+) stops", capsys.readouterr().err)
    assert said, "the command says the stops it used"
    assert float(said.group(1)) == pytest.approx(_expected_ev(img, 1.0), abs=0.005)  # printed to 2 decimals
