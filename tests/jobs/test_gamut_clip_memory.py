"""Clipping a wide-gamut file's colours outside sRGB costs no memory of its own: a display output of such an
image (a warp or a clip's frame written as PNG, JPEG or video, where the caller keeps its image) holds at its
peak no more than the same image developed without the clip. The clipped copy is the tone curve's to work in.

Measured with tracemalloc (NumPy reports its buffers to it), on one image, both ways in the same test: a
budget of bytes, not of time.
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np

from lenslab.io.registry import get
from lenslab.jobs.stages import Look, develop


def _peak(image: np.ndarray, meta: dict) -> int:
    x = image.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the notes are another test's)
        tracemalloc.start()
        try:
            develop(x, meta, get("png"), Look(tone="hable", exposure=0.0), in_place=False)
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()


def test_the_clip_adds_no_image_sized_buffer_to_a_display_output():
    image = np.random.default_rng(0).random((512, 512, 3), dtype=np.float32) * 2
    image[::3, :, 1] -= 0.5  # a colour outside sRGB on every third row
    before = image.copy()
    clipped = _peak(image, {"wide_gamut": "ICC profile 'Display P3'"})
    plain = _peak(image, {})
    assert clipped <= plain, (clipped / image.nbytes, plain / image.nbytes)
    np.testing.assert_array_equal(image, before)  # the caller's image is its own still
