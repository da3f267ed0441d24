"""Linear RGB on other primaries <-> Rec.709, one way for every reader and writer: an EXR's ``chromaticities``
attribute, a PNG's ``cICP`` primaries and a video stream's (P3-D65, BT.2020) give a 3 x 3 matrix from
colour-science (``matrix_RGB_to_RGB``, no chromatic adaptation: the light the file's primaries and white
describe, in Rec.709's), which :func:`to_rec709` applies to an image in place, a band of rows at a time (no
temporary of the image's size). The way back (Rec.709 to a stream's primaries, when a video is written) is
colour-science's matrix too, not an inverse computed here."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

#: rows converted at a time: a band's temporary stays small whatever the image's width
BAND_ROWS = 256
#: ITU-T H.273 colour primaries converted to and from Rec.709 (colour-science's names; the same D65 white, so
#: no adaptation): BT.2020 (9) and P3-D65 (12, SMPTE EG 432-1). Others (1 BT.709, 2 unspecified) are Rec.709.
H273_PRIMARIES = {9: "ITU-R BT.2020", 12: "P3-D65"}
REC709 = "ITU-R BT.709"
#: prefix of the matrices kept in lenslab's cache directory (:func:`lenslab.srgb.cached_table`)
CACHE_PREFIX = "primaries-v1"


def matrix_between(source, target=REC709, adaptation: str | None = None) -> np.ndarray:
    """float64 3 x 3 from linear RGB in ``source`` to linear RGB in ``target`` (colour-science colourspace names
    or ``RGB_Colourspace`` objects): ``colour.matrix_RGB_to_RGB``, without chromatic adaptation unless
    ``adaptation`` names colour-science's transform (``"Bradford"``)."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    spaces = colour.RGB_COLOURSPACES
    source = spaces[source] if isinstance(source, str) else source
    target = spaces[target] if isinstance(target, str) else target
    return np.asarray(colour.matrix_RGB_to_RGB(source, target, adaptation), dtype=np.float64)


def matrix_from_chromaticities(chromaticities, adaptation: str | None = None) -> np.ndarray:
    """float64 3 x 3 from linear RGB on ``chromaticities`` (x, y of R, G, B and white, OpenEXR's order)
    to linear Rec.709, by colour-science without chromatic adaptation (the file's XYZ, unchanged), or with
    colour-science's ``adaptation`` transform from the file's white to D65 (``"Bradford"``: an ICC profile's
    white becomes Rec.709's, :mod:`lenslab.io.colour.icc`); kept in lenslab's cache directory
    (:func:`lenslab.srgb.cached_table`), as the H.273 matrices are."""
    import hashlib

    from lenslab.srgb import cached_table

    c = np.asarray(chromaticities, dtype=np.float64).reshape(-1)[:8]

    def build():
        from lenslab.srgb import colour_science

        colour = colour_science()

        space = colour.RGB_Colourspace("file", c[:6].reshape(3, 2), c[6:8], use_derived_matrix_RGB_to_XYZ=True,
                                       use_derived_matrix_XYZ_to_RGB=True)
        return matrix_between(space, adaptation=adaptation).reshape(-1)

    # kept in lenslab's cache directory under the chromaticities' exact bits: a file of the same primaries (an
    # ICC profile's, an EXR's attribute) is read again without the import of colour-science (about 1 s of CPU)
    key = hashlib.sha256(np.ascontiguousarray(c).tobytes() + str(adaptation).encode()).hexdigest()[:24]
    return cached_table(f"chromaticities-{key}", 9, np.float64, build, prefix=CACHE_PREFIX).reshape(3, 3)


def check_chromaticities(path, chromaticities) -> None:
    """A :class:`~lenslab.errors.FormatError` (one line) unless ``chromaticities`` (x, y of R, G, B and white,
    OpenEXR's order) describe a colour space: finite numbers, the white strictly inside the triangle of the
    three primaries (so each primary adds light to white, whatever the sign of its y: ACES AP0's blue has y < 0).
    Two primaries at one point, a white with y = 0 or outside the triangle would give a singular or nearly
    singular matrix and meaningless colour."""
    from lenslab.errors import FormatError

    c = np.asarray(chromaticities, dtype=np.float64).reshape(-1)
    ok = c.size == 8 and bool(np.isfinite(c).all())
    if ok:
        (xr, yr), (xg, yg), (xb, yb), (xw, yw) = c.reshape(4, 2)
        area = (xg - xr) * (yb - yr) - (xb - xr) * (yg - yr)  # twice the triangle's signed area
        with np.errstate(all="ignore"):
            g = ((xw - xr) * (yb - yr) - (xb - xr) * (yw - yr)) / area  # the white's barycentric coordinates
            b = ((xg - xr) * (yw - yr) - (xw - xr) * (yg - yr)) / area
        ok = abs(area) > 1e-6 and g > 0 and b > 0 and 1.0 - g - b > 0 and yw > 1e-6
    if not ok:
        shown = ", ".join(f"{v:.6g}" for v in c[:8])
        raise FormatError(f"{path}: its chromaticities attribute ({shown}) describes no colour space (the white "
                          "must lie inside the triangle of red, green and blue); the file is damaged")


@lru_cache(maxsize=8)
def h273_matrix(primaries: int, to_709: bool = True) -> np.ndarray | None:
    """float64 3 x 3 (read-only) from linear RGB in the H.273 ``primaries`` to linear Rec.709 (``to_709``) or
    from Rec.709 to them (both colour-science's :func:`matrix_between`); None for primaries read as Rec.709.
    Kept in lenslab's cache directory, so that decoding a video needs no import of colour-science."""
    from lenslab.srgb import cached_table

    name = H273_PRIMARIES.get(int(primaries))
    if name is None:
        return None
    source, target = (name, REC709) if to_709 else (REC709, name)
    key = f"{int(primaries)}-{'to' if to_709 else 'from'}-709"
    m = cached_table(key, 9, np.float64, lambda: matrix_between(source, target).reshape(-1),
                     prefix=CACHE_PREFIX).reshape(3, 3).copy()
    m.flags.writeable = False
    return m


#: ITU-T H.273 matrix coefficients lenslab's Y'CbCr passes take (colour-science's ``WEIGHTS_YCBCR`` names): BT.709,
#: BT.601 (5 BT.470BG, 6 SMPTE 170M; also 2, unspecified: what FFmpeg codes an untagged clip made from RGB images
#: with and decodes it with, swscale's ``SWS_CS_DEFAULT``), BT.2020 non-constant luminance
H273_YCBCR = {1: "ITU-R BT.709", 2: "ITU-R BT.601", 5: "ITU-R BT.601", 6: "ITU-R BT.601", 9: "ITU-R BT.2020"}


@lru_cache(maxsize=8)
def ycbcr_weights(matrix: int) -> tuple[float, float]:
    """``(Kr, Kb)`` of the H.273 ``matrix`` coefficients (:data:`H273_YCBCR`): colour-science's ``WEIGHTS_YCBCR``,
    kept in lenslab's cache directory as the primaries matrices are."""
    from lenslab.srgb import cached_table

    name = H273_YCBCR[int(matrix)]

    def build():
        from lenslab.srgb import colour_science

        colour = colour_science()

        return np.asarray(colour.WEIGHTS_YCBCR[name], dtype=np.float64)

    kr, kb = cached_table(f"ycbcr-{name.replace(' ', '').replace('.', '')}", 2, np.float64, build, prefix=CACHE_PREFIX)
    return float(kr), float(kb)


def to_rec709(image: np.ndarray, matrix, rows: int = BAND_ROWS) -> np.ndarray:
    """Apply ``matrix`` (3 x 3, file RGB -> Rec.709) to the first three channels of ``image`` (float32 or
    float64 H x W x C, C >= 3; alpha and other channels untouched) in place, ``rows`` rows at a time, in
    the image's own precision. Returns ``image``."""
    m = np.asarray(matrix, dtype=image.dtype).T
    for r in range(0, image.shape[0], rows):
        band = image[r:r + rows, :, :3]
        band[...] = band @ m
    return image
