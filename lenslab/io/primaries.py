"""Linear RGB on other primaries -> Rec.709, one way for every reader: an EXR's ``chromaticities``
attribute and a PNG's ``cICP`` primaries (P3-D65, BT.2020) give a 3 x 3 matrix from colour-science
(``matrix_RGB_to_RGB``, no chromatic adaptation: the light the file's primaries and white describe, in
Rec.709's), which :func:`to_rec709` applies to an image in place, a band of rows at a time (no temporary
of the image's size)."""

from __future__ import annotations

import numpy as np

#: rows converted at a time: a band's temporary stays small whatever the image's width
BAND_ROWS = 256


def matrix_from_chromaticities(chromaticities, adaptation: str | None = None) -> np.ndarray:
    """float64 3 x 3 from linear RGB on ``chromaticities`` (x, y of R, G, B and white, OpenEXR's order)
    to linear Rec.709, by colour-science without chromatic adaptation (the file's XYZ, unchanged), or with
    colour-science's ``adaptation`` transform from the file's white to D65 (``"Bradford"``: an ICC profile's
    white becomes Rec.709's, :mod:`lenslab.io.icc`)."""
    import colour

    c = np.asarray(chromaticities, dtype=np.float64).reshape(-1)
    space = colour.RGB_Colourspace("file", c[:6].reshape(3, 2), c[6:8], use_derived_matrix_RGB_to_XYZ=True,
                                   use_derived_matrix_XYZ_to_RGB=True)
    return colour.matrix_RGB_to_RGB(space, colour.RGB_COLOURSPACES["ITU-R BT.709"], adaptation)


def to_rec709(image: np.ndarray, matrix, rows: int = BAND_ROWS) -> np.ndarray:
    """Apply ``matrix`` (3 x 3, file RGB -> Rec.709) to the first three channels of ``image`` (float32 or
    float64 H x W x C, C >= 3; alpha and other channels untouched) in place, ``rows`` rows at a time, in
    the image's own precision. Returns ``image``."""
    m = np.asarray(matrix, dtype=image.dtype).T
    for r in range(0, image.shape[0], rows):
        band = image[r:r + rows, :, :3]
        band[...] = band @ m
    return image
