"""What a warp checks of its output, band by band as each band is drawn (while its rows are still in cache
and on the thread that drew them), instead of in passes over the whole output after the bands.

A 4096x4096 RGB output is 268 MB: every pass over it (finite values, alpha in [0, 1], any coverage) costs
4-20 ms of memory traffic in the calling thread alone, and memory traffic does not scale with threads here
(``lenslab bench warp`` prints the machine's two-thread copy ratio). The engine uses these checks when the
bands drew the whole output (no falloff or tile after them), else it scans the output as before.
"""

from __future__ import annotations

import warnings

import numpy as np

from lenslab.io.alpha import has_alpha, settle
from lenslab.warp.filters import SAMPLED_COVERED, SAMPLED_NON_FINITE, all_finite, clamp_non_finite, finite_source


class OutputChecks:
    """Whether every band drawn so far holds finite values only (``finite``), coverage and the image's own
    alpha (when it carries one) in [0, 1] (``in_range``, NaN fails it), and some coverage (``covered``).

    ``image_alpha``: whether the image's last channel is alpha (:func:`lenslab.io.alpha.has_alpha`). Threads
    only ever turn ``finite`` and ``in_range`` to False and ``covered`` to True, so no lock is needed."""

    def __init__(self, image_alpha: bool, on_band=None):
        self.image_alpha = bool(image_alpha)
        self.on_band = on_band  # given each band's rows once checked (WarpPlan.run's on_band)
        self.finite = True
        self.in_range = True
        self.covered = False

    @classmethod
    def of(cls, channels: int, alpha_channel: bool | None, on_band=None) -> "OutputChecks":
        return cls(has_alpha(np.empty((0, 0, channels), np.float32), alpha_channel), on_band)

    def band(self, out: np.ndarray, alpha: np.ndarray, rows: slice | None = None, sampled: int | None = None) -> None:
        """Check a band's rows ``rows`` (then hand them to ``on_band``): ``out`` float32 h x W x C (C-contiguous)
        and ``alpha`` float32 h x W. ``sampled``: what the sampler that drew them said of them
        (:func:`lenslab.warp.filters.sample`'s flags; None: nothing, they are scanned)."""
        if not out.size:
            return
        if sampled is None:
            self._check(out, alpha)
        else:  # the sampler's word: its coverage is 0 or 1; only an image's own alpha is scanned
            if sampled & SAMPLED_NON_FINITE:
                self.finite = False
            if sampled & SAMPLED_COVERED:
                self.covered = True
            if self.image_alpha:
                self._check_image_alpha(out)
        if self.on_band is not None and rows is not None:
            self.on_band(out, rows)

    def _check_image_alpha(self, out: np.ndarray) -> None:
        a = out[..., -1]
        if not (a.min() >= 0.0 and a.max() <= 1.0):
            self.in_range = False

    def _check(self, out: np.ndarray, alpha: np.ndarray) -> None:
        if not all_finite(out):
            self.finite = False
        lo, hi = alpha.min(), alpha.max()
        if not (lo >= 0.0 and hi <= 1.0):
            self.in_range = False
        if self.image_alpha:
            self._check_image_alpha(out)
        if hi > 0.0:
            self.covered = True


#: what a warp says of a source that holds NaN or inf, which it reads as finite values
NON_FINITE_SOURCE = "the source has {bad} non-finite values: NaN read as 0, +-inf as the largest float32"


def finite_given(src: np.ndarray) -> np.ndarray:
    """``src`` as a warp by a given map (an ST map, :func:`lenslab.warp.warp_with_map`) reads it, as a lens-to-lens
    warp does (:func:`finite_output`): itself when all finite, else a copy with NaN read as 0 and +-inf as the
    largest float32, said in a RuntimeWarning (a map's taps would carry them into the output as NaN and inf)."""
    src, bad = finite_source(src)
    if bad:
        warnings.warn(NON_FINITE_SOURCE.format(bad=bad), RuntimeWarning, stacklevel=3)
    return src


def finite_output(render, src: np.ndarray, out: np.ndarray, alpha: np.ndarray, alpha_channel) -> str:
    """Make an output with NaN or inf finite, and say what happened: non-finite source values (NaN read as 0,
    +-inf as the largest float32, and the warp drawn again by ``render``, a plan's), or finite ones whose
    filtered sums passed float32's range (those outputs clamped)."""
    src, bad = finite_source(src)
    if bad:
        render(src, out, alpha, None, None, alpha_channel)
    over = clamp_non_finite(out)
    big = f"{np.finfo(np.float32).max:.3g}"
    said = NON_FINITE_SOURCE.format(bad=bad) if bad else ""
    if over:
        why = (f"{over} output values passed float32's range (+-{big}) in the warp's arithmetic (a filter's "
               f"weighted sum, the removal of vignetting); they were clamped to +-{big} (NaN: 0)")
        said = f"{said}; {why}" if said else f"the source is finite, but {why}"
    return said


class EmptyViewWarning(UserWarning):
    """A warp's output sees nothing of its source: every pixel has zero coverage."""


def settle_checked(out: np.ndarray, alpha: np.ndarray | None, alpha_channel, checks: "OutputChecks | None",
                   covered: bool | None = None) -> None:
    """Settle alpha (:func:`lenslab.io.alpha.settle`) unless the bands' ``checks`` (None: none cover the
    whole output) found it in range, and warn (:class:`EmptyViewWarning`) when nothing is covered: ``covered``
    (what the bands' checks saw of every band, None: not known), else what the coverage ``alpha`` holds
    (None: no coverage kept, which only a warp whose bands were all checked leaves)."""
    vouched = checks is not None and checks.in_range
    if not vouched:
        settle(out, alpha, alpha_channel)
    if covered is None:
        covered = checks.covered if vouched else (alpha is None or bool(alpha.any()))
    if not covered:
        h, w = out.shape[:2]
        warnings.warn(EmptyViewWarning(
            f"the {w}x{h} view sees nothing of the source (0% coverage): every pixel is empty; check the "
            "lenses, the pose and the source's field of view"), stacklevel=3)


def held_coverage(alpha: np.ndarray) -> np.ndarray | None:
    """The coverage plane a warp drew into, or None for the plane of one row that :func:`drawn_into` gives when
    none is kept (drawn a band at a time in scratch memory and dropped)."""
    return alpha if alpha.strides[0] or alpha.shape[0] == 1 else None


def drawn_into(into, shape: tuple[int, int, int], draws_all: bool, checked: bool):
    """``(image, coverage)`` a warp of output ``shape`` (h, w, C) draws into: ``into``'s when they fit (zeroed
    unless the bands draw every pixel, ``draws_all``), else new zeros. ``into = (image or None, None)``: the caller
    keeps no coverage (a source that carries its own alpha, an output without alpha): where every band's checks
    say whether any pixel is covered (``checked``) it is drawn a band at a time in scratch memory and never held
    (a plane whose rows are one row, :class:`lenslab.warp.kernels.dispatch.contiguous_rows`), and given back as
    None; elsewhere a plane of zeros as before."""
    h, w, _ = shape
    image, coverage = into if into is not None else (None, np.zeros((h, w), np.float32))
    fits = image is not None and image.shape == shape and image.dtype == np.float32
    if coverage is None:  # none kept
        coverage = np.lib.stride_tricks.as_strided(np.zeros(w, np.float32), (h, w), (0, 4), writeable=True) \
            if checked else np.zeros((h, w), np.float32)
    elif into is not None and not (fits and coverage.shape == (h, w) and coverage.dtype == np.float32):
        fits, coverage = False, np.zeros((h, w), np.float32)  # (the caller's two are taken together or not at all)
    if not fits:
        return np.zeros(shape, np.float32), coverage
    if not draws_all:
        image.fill(0.0)
        coverage.fill(0.0)
    return image, coverage


def checked_source(image, camera) -> np.ndarray:
    """``image`` as a float32 H x W x C source for ``camera`` (a 2-D image gets one channel); WarpError when
    its size is not the camera's or it does not hold real numbers."""
    from lenslab.errors import WarpError, check_image_shape

    arr = check_image_shape(image, channels=None)
    h, w = arr.shape[:2]
    if (w, h) != camera.size:
        raise WarpError(
            f"the image is {w}x{h} but the source camera is {camera.width}x{camera.height}; "
            "give a source camera of the image's size (e.g. Camera(lens.with_size(w, h), pose))")
    if not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise WarpError(f"the image must hold real numbers, got dtype {arr.dtype}")
    arr3 = arr[..., None] if arr.ndim == 2 else arr
    return np.ascontiguousarray(arr3, dtype=np.float32)
