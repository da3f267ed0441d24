"""``fit tone`` counts the slight negatives of its HDR image once, as the one image they are in, however many
times its optimiser tone-maps that image (each evaluation repairs the same values again)."""

from __future__ import annotations

import numpy as np

import lenslab
from lenslab.fit import fit_tone
from lenslab.tone import repairs


def test_negatives_are_counted_once_for_one_image():
    hdr = np.random.default_rng(2).uniform(0.05, 4.0, (16, 16, 3)).astype(np.float32)
    placed = [(0, 0, 0), (3, 5, 1), (7, 2, 2), (9, 9, 0), (15, 15, 1)]  # 5 values, as a DWAB file leaves them
    for y, x, c in placed:
        hdr[y, x, c] = -1e-4
    ldr = lenslab.tonemap(np.clip(hdr, 0, None), "reinhard", exposure=1.0)
    repairs.take()  # start from an empty tally
    fit = fit_tone(hdr, ldr, "reinhard")
    assert fit.optimizer.evaluations > 5  # the optimiser tone-mapped the image many times
    values, images, lowest = repairs.take()
    assert (values, images) == (len(placed), 1)
    assert lowest == np.float32(-1e-4)
