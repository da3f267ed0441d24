"""Reconstruction filters: read a float32 source at fractional positions, exactly.

Each sampler takes a band of the map (source index coordinates per output sample, the centre of
source pixel ``(i, j)`` at ``(i, j)``) and returns, per output pixel, the *sum of its valid samples
divided by the number of samples* (colour premultiplied by coverage) and the coverage itself.

Filters (separable, weights computed in float64 from the exact fractional position; the registry
:data:`lenslab.filters.FILTERS` names them, with their support radius and references):

- ``nearest``: the pixel whose centre is nearest (ties go right/down);
- ``bilinear``: the 2x2 tent, ``w(t) = 1 - |t|``;
- ``bicubic``: Catmull-Rom (Keys' cubic with ``a = -0.5``), 4x4 taps; interpolating, reproduces
  quadratics, overshoots a little at sharp edges (never clamped: HDR stays HDR);
- ``lanczos``: Lanczos-3 windowed sinc, 6x6 taps, weights normalised to sum to 1.

A finite source gives a finite output: where the overshoot of bicubic or lanczos next to a value
near float32's largest would pass it, the output holds the largest float32 (as +-inf in a source
is read, see :func:`finite_source`).

Why not ``cv2.remap``: with float maps cv2 rounds the fractional position to 1/32 pixel
(``INTER_BITS = 5``), an error of up to 1/64 pixel times the local gradient; in HDR images with
sharp bright sources that reaches percent-level errors per pixel (measured by ``lenslab bench warp``),
and it cannot fold taps across the poles. These samplers use the exact position, fold every tap
through :mod:`lenslab.warp.seam` and run in C++, compiled ahead of time, one band of rows per thread
(:mod:`lenslab.warp.kernels.native`; NumPy references in :mod:`lenslab.warp.kernels.reference`).
Bilinear lerps are float32 (exact at pixel centres; 2^-24 relative elsewhere), the other weights float64.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import WarpError
from lenslab.filters import FILTERS as REGISTRY
from lenslab.warp.kernels import native
from lenslab.warp.kernels.native import c32, cbool
from lenslab.warp.seam import Border

#: the filters' canonical names, in the registry's order
FILTERS = tuple(REGISTRY)
#: the largest float32: where a filter's overshoot would pass it, the output holds it instead of inf
F32_MAX = float(np.finfo(np.float32).max)


def sample(src: np.ndarray, xs: np.ndarray, ys: np.ndarray, valid: np.ndarray, border: Border, filter: str,
           out: np.ndarray, alpha: np.ndarray, zeroed: bool = False) -> None:
    """Read ``src`` at a band of map positions with one of :data:`FILTERS`, in place.

    A source whose pieces have neighbours (``border.has_pieces``, a cube map) is read through the
    separable sampler, whose taps leaving a sample's piece read the neighbouring piece.

    Parameters
    ----------
    src : numpy.ndarray
        float32 ``H x W x C``, C-contiguous.
    xs, ys : numpy.ndarray
        ``h x w x S`` index coordinates of ``S`` samples per output pixel (the centre of source pixel
        ``(i, j)`` at ``(i, j)``).
    valid : numpy.ndarray
        bool ``h x w x S``: the samples that land on the source.
    border : lenslab.warp.seam.Border
        How taps past the edge are read: wrapped, folded over a pole, or clamped (``Border()``).
    filter : str
        ``nearest``, ``bilinear``, ``bicubic`` or ``lanczos``.
    out : numpy.ndarray
        float32 ``h x w x C``, filled with the sum of the valid samples over ``S`` (premultiplied).
    alpha : numpy.ndarray
        float32 ``h x w``, filled with the share of valid samples.
    zeroed : bool
        ``out`` and ``alpha`` hold +0 already (fresh zeroed memory): the single-sample bilinear kernel then leaves
        the pixels without a valid sample alone, so the pages of an output a photo leaves unseen are never touched.

    Returns
    -------
    int or None
        ``out`` and ``alpha`` are filled in place (the engine hands each thread its rows). The single-sample
        bilinear kernel also says what it wrote, while the values were in registers (no second pass over the
        rows): :data:`SAMPLED_NON_FINITE` when some value is NaN or infinite, :data:`SAMPLED_COVERED` when some
        sample is valid (its alpha is 0 or 1, always in range). None from the other kernels.

    Examples
    --------
    Halfway between two pixel centres, bilinear gives their mean and Catmull-Rom (bicubic) its own
    weights ``-1/16, 9/16, 9/16, -1/16``: (9 + 27 - 8) / 16 = 1.75:

    >>> import numpy as np
    >>> from lenslab.warp.filters import sample
    >>> from lenslab.warp.seam import Border
    >>> src = np.array([[[0.0], [1.0], [3.0], [8.0]]], np.float32)  # one row of four pixels
    >>> xs, ys = np.full((1, 1, 1), 1.5), np.zeros((1, 1, 1))
    >>> out, alpha = np.zeros((1, 1, 1), np.float32), np.zeros((1, 1), np.float32)
    >>> for name in ("nearest", "bilinear", "bicubic"):
    ...     said = sample(src, xs, ys, np.ones((1, 1, 1), bool), Border(), name, out, alpha)
    ...     print(name, float(out[0, 0, 0]), float(alpha[0, 0]))
    nearest 3.0 1.0
    bilinear 2.0 1.0
    bicubic 1.75 1.0
    """
    kind = REGISTRY[filter].code  # the compiled kernel; its support radius too (nearest: 1 tap)
    for name, a in (("out", out), ("alpha", alpha)):  # written in place: the kernels take no other layout
        if not (isinstance(a, np.ndarray) and a.dtype == np.float32 and a.flags.c_contiguous and a.flags.writeable):
            raise WarpError(f"sample: {name} must be a writable C-contiguous float32 array, not "
                            f"{getattr(a, 'dtype', type(a).__name__)}{'' if getattr(a, 'flags', None) is None or a.flags.c_contiguous else ' (strided)'}")
    wrap, top, bottom = border.flags
    k = native.kernels()
    if kind == 1 and not border.has_pieces:  # float32 lerps
        sh, sw, nc = src.shape
        if xs.shape[2] == 1:
            return k.bilinear1(src.reshape(-1), sw, sh, nc, c32(xs), c32(ys), cbool(valid), wrap, top, bottom, out,
                               alpha, bool(zeroed))
        k.bilinear_n(src.reshape(-1), sw, sh, nc, c32(xs), c32(ys), cbool(valid), wrap, top, bottom, out, alpha)
    else:  # float64 weights, taps folded into the neighbouring piece where the source has pieces
        cw, ch = border.cell
        k.separable(src, c32(xs), c32(ys), cbool(valid), wrap, top, bottom, border.pieces, border.grid, cw, ch, kind,
                    out, alpha)
    return None


#: what :func:`sample`'s single-sample bilinear kernel says of a band it wrote (src/native/sampler.h)
SAMPLED_NON_FINITE = 1
SAMPLED_COVERED = 2


def all_finite(a: np.ndarray) -> bool:
    """True when every value of ``a`` is finite (no temporary arrays for float32; a large array in pieces on
    the engine's threads, compiled ahead of time)."""
    from lenslab.warp.kernels.dispatch import run_bands

    if a.dtype != np.float32:
        return bool(np.isfinite(a).all())
    if not a.flags.c_contiguous and a.ndim > 1 and a.shape[0] > 1:  # (strided: rows at a time, not a copy)
        rows = max(1, (16 << 20) // max(1, a[:1].size * 4))
        return all(all_finite(np.ascontiguousarray(a[i:i + rows])) for i in range(0, a.shape[0], rows))
    flat = np.ascontiguousarray(a).reshape(-1)
    check = native.kernels().all_finite
    step = max(1 << 22, -(-flat.size // 8))
    if flat.size <= step:
        return bool(check(flat))
    return all(run_bands([flat[i:i + step] for i in range(0, flat.size, step)], check))


def clamp_non_finite(out: np.ndarray) -> int:
    """Make ``out`` (float32) finite in place, NaN -> 0 and +-inf -> +-float32 max; the count of values changed."""
    if all_finite(out):
        return 0
    n = int(np.count_nonzero(~np.isfinite(out)))
    big = np.finfo(np.float32).max
    np.nan_to_num(out, copy=False, nan=0.0, posinf=big, neginf=-big)
    return n


def finite_source(src: np.ndarray) -> tuple[np.ndarray, int]:
    """``src`` itself when all finite, else a copy with NaN -> 0 and +-inf -> +-float32 max; and the count."""
    if all_finite(src):
        return src, 0
    bad = int(np.count_nonzero(~np.isfinite(src)))
    big = np.finfo(np.float32).max
    return np.nan_to_num(src, nan=0.0, posinf=big, neginf=-big), bad
