"""A warp's colour and alpha joined into one image in the colour's own memory (:func:`lenslab.io.alpha.joined_alpha`)
hold what NumPy's ``concatenate`` of the two gives, whatever the size, channel count and band height; colour and
alpha that are views of one image are that image."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.io.alpha import joined_alpha, room_for_alpha


@settings(max_examples=60, deadline=None)
@given(h=st.integers(1, 40), w=st.integers(1, 9), c=st.integers(1, 3), rows=st.integers(1, 50),
       seed=st.integers(0, 2 ** 32 - 1))
def test_joined_in_place_is_numpys_concatenation(h, w, c, rows, seed):
    rng = np.random.default_rng(seed)
    colour, alpha = room_for_alpha(h, w, c)
    colour[...] = rng.standard_normal((h, w, c), dtype=np.float32)
    alpha[...] = rng.random((h, w), dtype=np.float32)
    expected = np.concatenate([colour, alpha[..., None]], axis=-1)  # NumPy's answer, before the memory is reused
    address = colour.ctypes.data
    joined = joined_alpha(colour, alpha, rows=rows)
    assert joined.shape == (h, w, c + 1) and joined.ctypes.data == address  # in the colour's memory
    np.testing.assert_array_equal(joined, expected)


def test_views_of_one_image_are_that_image():
    image = np.arange(4 * 5 * 4, dtype=np.float32).reshape(4, 5, 4)
    joined = joined_alpha(image[..., :-1], image[..., -1])
    assert joined.ctypes.data == image.ctypes.data and joined.strides == image.strides
    np.testing.assert_array_equal(joined, np.arange(4 * 5 * 4, dtype=np.float32).reshape(4, 5, 4))


def test_arrays_of_their_own_are_not_joined_in_place():
    colour = np.ones((4, 5, 3), np.float32)  # (the caller then makes a new image, as before)
    assert joined_alpha(colour, np.ones((4, 5), np.float32)) is None
    assert joined_alpha(np.ones((4, 5, 4), np.float32)[..., :2], np.ones((4, 5), np.float32)) is None
