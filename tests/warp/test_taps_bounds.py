"""The cached-taps sampler (``from_taps``) refuses any tap whose 2x2 window leaves the source's memory, wherever it
sits in the band (the check runs as a vectorised loop: its body and its tail are both covered), and takes the
largest offset that stays inside: the top-left tap at flat index ``W H - W - 2`` reads up to index ``W H - 1``, the
last pixel; one more reads past it."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.warp.kernels import native

FOLDED, INVALID = 0xFFFFFFFE, 0xFFFFFFFF


@pytest.mark.parametrize("sw,sh,nc", [(4, 3, 1), (7, 5, 3), (64, 32, 4)])
@pytest.mark.parametrize("n,at", [(1, 0), (37, 36), (64, 17), (1000, 999), (1000, 3)])
def test_one_tap_past_the_source_is_refused_anywhere_in_the_band(sw, sh, nc, n, at):
    k = native.kernels()
    src = np.zeros(sw * sh * nc, np.float32)
    last_inside = sw * sh - sw - 2  # its taps: last_inside, +1, +sw, +sw+1 = sw * sh - 1
    off = np.resize(np.array([0, last_inside, FOLDED, INVALID], np.uint32), n)
    w = np.zeros(n, np.float32)
    out, alpha = np.zeros(n * nc, np.float32), np.zeros(n, np.float32)
    k.from_taps(src, sw, nc, off, w, w, out, alpha)  # all inside
    for bad in (last_inside + 1, sw * sh, FOLDED - 1):
        off_bad = off.copy()
        off_bad[at] = bad
        with pytest.raises(ValueError, match="a tap reads outside the source"):
            k.from_taps(src, sw, nc, off_bad, w, w, out, alpha)
