"""Every band of a warp reads the same sub-pixel offsets: :func:`lenslab.warp.maps.sample_pattern` makes them once
per count and hands out one read-only array (a band that wrote into it would move every later warp's samples).
The values are the strata centres of a k x k grid, ``((i + 1/2) / k, (j + 1/2) / k)``, transcribed here."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.warp.maps import sample_pattern


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_the_pattern_is_the_strata_centres_made_once_and_read_only(k):
    first = sample_pattern(k * k)
    assert sample_pattern(k * k) is first
    assert not first.flags.writeable
    with pytest.raises(ValueError):
        first[0, 0] = 0.25
    want = {((i + 0.5) / k, (j + 0.5) / k) for i in range(k) for j in range(k)}
    assert first.shape == (k * k, 2) and set(map(tuple, first.tolist())) == want
