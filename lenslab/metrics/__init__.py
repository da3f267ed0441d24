"""Image error metrics for comparing a warped (or otherwise approximated) HDR image with a reference.

Every metric is a pure function of two linear-light float images ``H x W x C`` and a boolean mask of
the pixels to compare (``H x W``), and returns plain Python floats. The mask is normally
:func:`valid_mask`: the pixels fully covered in both images (alpha = 1), so that the rim of a fisheye,
the missing tile of a grid or a pixel the warp could not fill never counts as error.

Definitions (``r`` reference, ``t`` test, sums over masked pixels and all colour channels):

- **relative L1** ``sum |t - r| / sum |r|``: the aggregate form, stable where the reference is dark.
- **PSNR of log radiance**: ``10 log10(peak^2 / mean((log(t+e) - log(r+e))^2))`` with ``e`` a floor of
  ``1e-3`` times the mean reference value and ``peak`` the range of ``log(r+e)`` over the mask; it weighs
  an error in a shadow like the same relative error in a highlight.
- **share off by more than 5%**: the fraction of masked pixels whose per-pixel relative error
  ``sum_c |t - r| / max(sum_c r, floor)`` exceeds 0.05 (``floor`` = 1% of the mean pixel sum, so that
  near-black pixels are judged by an absolute error instead of dividing by zero).
- **FLIP** (NVIDIA's perceptual difference, ``flip-evaluator``) on the two images tone-mapped by the
  same curve and exposure and sRGB-encoded, averaged over the mask.
- **Monte Carlo noise floor**: a reference traced with ``n`` samples per pixel carries a per-pixel
  standard error ``sigma = sqrt(var / n)``. Against an exact test image, that noise alone gives an
  expected relative L1 of ``sqrt(2/pi) sum sigma / sum |r|`` (the mean absolute value of a normal
  variable). It is reported next to the measured error so a warp is never blamed for the reference's
  noise; the excess is what the warp itself adds. Monte Carlo noise at a few samples per pixel is
  heavy-tailed, which makes that normal formula pessimistic; rendering the reference as two halves
  with independent seeds gives an estimate free of that assumption (:func:`noise_floor_split`).
- **edge masks**: pixels within ``radius`` pixels of a silhouette or shadow edge, found from
  depth / normal / primitive-id discontinuities when the renderer provides them and from the gradients
  of the (denoised) log luminance of the reference otherwise. Errors are reported on the edges and on
  the rest separately (:func:`compare`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from lenslab.metrics.edges import dilate, edge_mask_from_aovs, edge_mask_from_image
from lenslab.metrics.measures import (FULL_COVERAGE, as_image, to_display, error_map, flip,  # noqa: F401
                                      pixel_relative_error, psnr_log, relative_l1, rmse, share_off, valid_mask)
from lenslab.metrics.noise import noise_floor, noise_floor_split

__all__ = [
    "valid_mask", "relative_l1", "psnr_log", "share_off", "flip", "noise_floor", "noise_floor_split", "rmse",
    "edge_mask_from_aovs", "edge_mask_from_image", "dilate", "error_map", "compare",
]


# -- everything at once --------------------------------------------------------------------------
def compare(ref: ArrayLike, test: ArrayLike, ref_alpha: ArrayLike | None = None,
            test_alpha: ArrayLike | None = None, mask: ArrayLike | None = None, edges: ArrayLike | None = None,
            ref_stderr: ArrayLike | None = None, with_flip: bool = True, tone_curve: str = "hable",
            exposure: float = 0.0, ref_halves: tuple[ArrayLike, ArrayLike] | None = None) -> dict[str, Any]:
    """All metrics of ``test`` against ``ref``: overall, on the edges and away from them.

    Parameters
    ----------
    ref, test : array_like
        Linear images of one shape, ``H x W x C`` or ``H x W``.
    ref_alpha, test_alpha : array_like, optional
        Their coverage; ``mask`` defaults to :func:`valid_mask` of the two.
    mask : array_like, optional
        Boolean ``H x W``: the pixels to compare.
    edges : array_like, optional
        Boolean ``H x W`` edge mask (:func:`edge_mask_from_aovs`, :func:`edge_mask_from_image`); without
        it only the overall figures are given.
    ref_stderr : array_like, optional
        The reference's per-pixel standard error: adds its noise floor (overall and per region) and
        ``excess_l1``, the measured relative L1 minus the floor (never negative; a lower bound of the
        error the test itself adds).
    with_flip : bool
        Also compute FLIP (:func:`flip`), the slowest of the measures.
    tone_curve : str
        The tone curve FLIP sees both images through.
    exposure : float
        Exposure in stops before that curve.
    ref_halves : tuple of array_like, optional
        ``(a, b)``, two independent half-sample renders whose mean is the reference: the floor is then
        the empirical :func:`noise_floor_split` (the normal formula is reported as ``noise_l1_normal``).

    Returns
    -------
    dict
        A flat dict of floats: ``l1``, ``psnr_log``, ``off5``, ``rmse``, ``flip``, ``pixels``, and the
        same with ``_edge`` / ``_interior`` suffixes, plus ``noise_l1*`` and ``excess_l1*``.

    Raises
    ------
    ValueError
        Images, alphas or masks of different shapes.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import compare
    >>> ref = np.ones((4, 4, 3))
    >>> test = ref.copy(); test[0, 0] = 2.0  # one pixel of 16 twice as bright
    >>> alpha = np.ones((4, 4)); alpha[3, 3] = 0.0  # one pixel the warp did not cover
    >>> out = compare(ref, test, test_alpha=alpha, with_flip=False)
    >>> out["pixels"], out["l1"], out["off5"]  # 3 / 45 and 1 / 15
    (15, 0.06666666666666667, 0.06666666666666667)
    """
    r = as_image(ref, "reference")
    if mask is None:
        mask = valid_mask(ref_alpha, test_alpha, shape=r.shape[:2])
    mask = np.asarray(mask, dtype=bool)
    regions = {"": mask}
    if edges is not None:
        e = np.asarray(edges, dtype=bool)
        regions["_edge"] = mask & e
        regions["_interior"] = mask & ~e
    out: dict[str, Any] = {}
    for suffix, m in regions.items():
        out["pixels" + suffix] = int(m.sum())
        out["l1" + suffix] = relative_l1(r, test, m)
        out["psnr_log" + suffix] = psnr_log(r, test, m)
        out["off5" + suffix] = share_off(r, test, m)
        out["rmse" + suffix] = rmse(r, test, m)
        floor = None
        if ref_stderr is not None:
            floor = noise_floor(r, ref_stderr, m)["l1"]
        if ref_halves is not None:
            if floor is not None:
                out["noise_l1_normal" + suffix] = floor
            floor = noise_floor_split(ref_halves[0], ref_halves[1], m)
        if floor is not None:
            out["noise_l1" + suffix] = floor
            out["excess_l1" + suffix] = max(out["l1" + suffix] - floor, 0.0) if np.isfinite(floor) \
                else out["l1" + suffix]
    if with_flip:
        mean, fmap = flip(r, test, mask, curve=tone_curve, exposure=exposure, return_map=True)
        out["flip"] = mean
        if edges is not None:
            for suffix in ("_edge", "_interior"):
                m = regions[suffix]
                out["flip" + suffix] = float(fmap[m].mean()) if m.any() else float("nan")
    return out
