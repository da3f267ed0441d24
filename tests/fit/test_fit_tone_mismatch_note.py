"""``fit tone`` of two images that do not show the same view says so: a note when the mean CIEDE2000 left
after the fit is above 10 (colour-science's CIEDE2000 of the fitted render against the LDR image, computed
here), none for a matched pair."""

from __future__ import annotations

import colour
import numpy as np

import lenslab
from lenslab.fit import fit_tone


def _mean_de(fit, hdr, ldr) -> float:
    shown = lenslab.tonemap(hdr, fit.curve, fit.exposure, **fit.params).astype(np.float64)
    lab = [colour.XYZ_to_Lab(colour.sRGB_to_XYZ(np.clip(im, 0, 1), apply_cctf_decoding=False)) for im in (shown, ldr)]
    return float(np.mean(colour.delta_E(lab[0], lab[1], method="CIE 2000")))


def test_unrelated_images_get_a_note():
    rng = np.random.default_rng(4)
    hdr = rng.uniform(0.0, 4.0, (24, 24, 3)).astype(np.float32)
    ldr = np.zeros((24, 24, 3), np.float32)
    ldr[..., 1] = np.linspace(0, 1, 24)[None, :]  # a green ramp: no curve of the noise gives it
    fit = fit_tone(hdr, ldr, "reinhard")
    de = _mean_de(fit, hdr, ldr)
    assert de > 10, de
    notes = [n for n in fit.notes if "CIEDE2000" in n]
    assert len(notes) == 1 and f"{de:.3g}" in notes[0], (notes, de)


def test_a_matched_pair_gets_none():
    hdr = np.random.default_rng(1).uniform(0.0, 4.0, (16, 16, 3)).astype(np.float32)
    ldr = lenslab.tonemap(hdr, "reinhard", exposure=1.0)
    fit = fit_tone(hdr, ldr, "reinhard")
    assert _mean_de(fit, hdr, ldr) < 1e-3
    assert not [n for n in fit.notes if "CIEDE2000" in n]
