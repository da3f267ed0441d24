"""A warp's colour and alpha drawn into the channels of one image (:func:`lenslab.io.alpha.room_for_alpha`) are
that image without a copy (:func:`lenslab.io.alpha.joined_alpha`), holding what NumPy's ``concatenate`` of the two
gives; the warp engine draws into such strided outputs what it draws into arrays of their own."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.io.alpha import joined_alpha, room_for_alpha


@settings(max_examples=40, deadline=None)
@given(h=st.integers(1, 30), w=st.integers(1, 9), c=st.integers(1, 3), seed=st.integers(0, 2 ** 32 - 1))
def test_the_channels_joined_are_numpys_concatenation(h, w, c, seed):
    rng = np.random.default_rng(seed)
    colour, alpha = room_for_alpha(h, w, c)
    colour[...] = rng.standard_normal((h, w, c), dtype=np.float32)
    alpha[...] = rng.random((h, w), dtype=np.float32)
    expected = np.concatenate([colour, alpha[..., None]], axis=-1)  # NumPy's answer
    joined = joined_alpha(colour, alpha)
    assert joined.shape == (h, w, c + 1) and joined.ctypes.data == colour.ctypes.data  # no copy
    np.testing.assert_array_equal(joined, expected)


def test_arrays_of_their_own_are_not_joined():
    colour = np.ones((4, 5, 3), np.float32)  # (the caller then makes a new image, as before)
    assert joined_alpha(colour, np.ones((4, 5), np.float32)) is None
    image = np.ones((4, 5, 4), np.float32)
    assert joined_alpha(image[..., :2], image[..., 3]) is None  # a channel between them


@pytest.mark.parametrize("options", [{}, {"max_map_bytes": 0}, {"filter": "bicubic"}, {"filter": "nearest"},
                                     {"antialias": True}, {"samples": 4, "seed": 1}])
def test_the_engine_draws_into_strided_outputs_what_it_draws_into_its_own(options):
    from lenslab.lenses import Camera
    from lenslab.warp.batch import PlanCache

    src, dst = Camera.from_spec("equirect", (128, 64)), Camera.from_spec("fisheye:fov=180", (40, 30))
    pano = np.random.default_rng(5).random((64, 128, 3), dtype=np.float32) * 3
    cache = PlanCache(**options)
    own = [a.copy() for a in cache.warp_frame(pano, src, dst)]  # (kept maps: the next run draws every pixel)
    colour, alpha = room_for_alpha(30, 40, 3)  # uninitialised
    drawn = cache.warp_frame(pano, src, dst, into=(colour, alpha))
    assert drawn[0] is colour and drawn[1] is alpha and alpha.max() == 1.0
    np.testing.assert_array_equal(colour, own[0])
    np.testing.assert_array_equal(alpha, own[1])
    pano[30:34, 60:68] = np.nan  # drawn again with the source made finite, into the same arrays
    with pytest.warns(RuntimeWarning):
        own = [a.copy() for a in cache.warp_frame(pano, src, dst)]
        drawn = cache.warp_frame(pano, src, dst, into=(colour, alpha))
    np.testing.assert_array_equal(colour, own[0])
    np.testing.assert_array_equal(alpha, own[1])
