"""Compare two images as OpenImageIO's ``idiff`` does, plus relative errors, PSNR and FLIP.

:func:`diff_images` takes two float images ``H x W x C`` (as :func:`lenslab.io.read` gives them: linear
light, premultiplied by alpha) and returns a :class:`DiffReport`. Definitions, over the compared pixels
(``n`` of them) and channels, with ``d = |a - b|``:

- **mean**, **RMS** and **max** absolute error: ``mean d``, ``sqrt(mean d^2)``, ``max d`` (the max with its
  pixel and channel), per channel and over all channels. Over all channels they are OpenImageIO's
  ``ImageBufAlgo.compare`` ``meanerror``, ``rms_error`` and ``maxerror``.
- **relative error** ``d / ((|a| + |b|) / 2)`` (0 where both are 0): OpenImageIO's relative measure
  (``idiff -failrelative``); its mean, RMS and max per channel.
- **PSNR** ``20 log10(peak / RMS)`` with ``peak`` the largest absolute value in either image, or 1 if
  that is smaller, as OpenImageIO computes it (inf for identical images).
- **over a threshold**: a pixel *fails* when any channel has ``d > fail`` and, with ``fail_relative``,
  a relative error above it too; likewise *warns* (``warn``, ``warn_relative``). The counts are
  ``compare``'s ``nfail``/``nwarn``; the report gives their share of the compared pixels.
- **FLIP** (NVIDIA, ``flip-evaluator``): HDR-FLIP of the linear images when either holds a value above
  1, else LDR-FLIP of their sRGB encodings (or as asked), averaged over the compared pixels.

The verdict follows ``idiff``: PASS (0) unless more than ``fail_percent`` % of the pixels fail or the
max error exceeds ``hard_fail`` (FAILURE, 2), or likewise for the warning thresholds (WARNING, 1);
at most ``allow_failures`` failing pixels always pass.

**Masks by alpha**: when either image has alpha (4 channels), only pixels fully covered in both
(alpha >= :data:`~lenslab.metrics.measures.FULL_COVERAGE`) are compared, and the colour channels only;
``mask_alpha=False`` compares every pixel and every channel, alpha included, as ``idiff`` does.
A pixel with NaN or infinity in either image (and not the same value in both) is left out of the means
and counted as failing; the report says how many.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import LenslabError
from lenslab.metrics.measures import FULL_COVERAGE

PASS, WARNING, FAILURE = 0, 1, 2
VERDICTS = {PASS: "PASS", WARNING: "WARNING", FAILURE: "FAILURE"}
FLIP_MODES = ("auto", "hdr", "ldr", "off")


class DiffError(LenslabError):
    """The two images cannot be compared (sizes or channels differ)."""


@dataclass(frozen=True)
class Thresholds:
    """``idiff``'s thresholds (its defaults: 1e-6 absolute, no relative, no share allowed)."""

    fail: float = 1e-6
    warn: float = 1e-6
    fail_relative: float = 0.0
    warn_relative: float = 0.0
    fail_percent: float = 0.0
    warn_percent: float = 0.0
    hard_fail: float = math.inf
    hard_warn: float = math.inf
    allow_failures: int = 0


@dataclass
class ChannelStats:
    name: str
    mean_abs: float
    rms_abs: float
    max_abs: float
    max_at: tuple[int, int] | None
    mean_rel: float
    rms_rel: float
    max_rel: float


@dataclass
class DiffReport:
    """Everything :func:`diff_images` measured (see the module docstring); :meth:`to_dict` for JSON."""

    width: int
    height: int
    channels: list[str]
    pixels: int
    masked_out: int
    nonfinite: int
    mean_error: float
    rms_error: float
    psnr: float
    max_error: float
    max_at: tuple[int, int, str] | None
    per_channel: list[ChannelStats]
    nwarn: int
    nfail: int
    warn_share: float
    fail_share: float
    flip: float | None
    flip_mode: str
    thresholds: Thresholds
    verdict: int = PASS
    values_at_max: tuple[list[float], list[float]] | None = field(default=None)

    @property
    def verdict_name(self) -> str:
        return VERDICTS[self.verdict]

    def to_dict(self) -> dict:
        out = asdict(self)
        out["verdict"] = self.verdict_name
        out["exit_code"] = self.verdict
        return _json_safe(out)


def _json_safe(value):
    """inf and NaN as strings (JSON has neither), tuples as lists."""
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def channel_names(c: int) -> list[str]:
    return {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}.get(c, [f"c{i}" for i in range(c)])


def _as3(a, what: str) -> np.ndarray:
    arr = np.asarray(a)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.ndim != 3 or arr.size == 0:
        raise DiffError(f"the {what} image must be H x W or H x W x C, got shape {arr.shape}")
    return arr


def prepare(a, b, mask_alpha: bool = True):
    """The channels to compare of both images (float64), their names and the mask of pixels compared."""
    a, b = _as3(a, "first"), _as3(b, "second")
    if a.shape[:2] != b.shape[:2]:
        raise DiffError(f"the images differ in size: {a.shape[1]}x{a.shape[0]} and {b.shape[1]}x{b.shape[0]}")
    na, nb = channel_names(a.shape[2]), channel_names(b.shape[2])
    mask = np.ones(a.shape[:2], dtype=bool)
    if mask_alpha and ("A" in na or "A" in nb):
        for img, names in ((a, na), (b, nb)):
            if "A" in names:
                alpha = img[..., names.index("A")].astype(np.float64)
                mask &= np.isfinite(alpha) & (alpha >= FULL_COVERAGE)
        a = a[..., [i for i, n in enumerate(na) if n != "A"]]
        b = b[..., [i for i, n in enumerate(nb) if n != "A"]]
        na, nb = [n for n in na if n != "A"], [n for n in nb if n != "A"]
    if na != nb:
        raise DiffError(f"the images have different channels: {','.join(na)} and {','.join(nb)}")
    return a, b, na, mask


def relative_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``|a - b| / ((|a| + |b|) / 2)``, 0 where both are 0 (float64)."""
    d = np.abs(a - b)
    den = 0.5 * (np.abs(a) + np.abs(b))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, d / np.where(den > 0, den, 1.0), 0.0)


def _over(d, rel, thresh, rel_thresh):
    hit = d > thresh
    if rel_thresh > 0:
        hit &= rel > rel_thresh
    return hit.any(axis=-1)


def verdict(nfail: int, nwarn: int, pixels: int, max_error: float, t: Thresholds) -> int:
    """idiff's decision: at most ``allow_failures`` failing pixels pass; then FAILURE, WARNING, PASS."""
    if nfail <= t.allow_failures:
        return PASS
    if nfail > t.fail_percent / 100.0 * pixels or max_error > t.hard_fail:
        return FAILURE
    if nwarn > t.warn_percent / 100.0 * pixels or max_error > t.hard_warn:
        return WARNING
    return PASS


#: pixels per chunk: the float64 work arrays of one chunk stay near 50 MB whatever the image size
CHUNK = 1 << 20


class _Sums:
    """Running per-channel sums, maxima (with the flat index of their first pixel) and counts."""

    def __init__(self, c: int):
        self.n = 0
        self.d, self.d2, self.r, self.r2 = (np.zeros(c) for _ in range(4))
        self.dmax, self.rmax = np.full(c, -1.0), np.full(c, -1.0)
        self.dat = np.zeros(c, dtype=np.int64)
        self.peak = 1.0  # PSNR's peak is never below 1
        self.nwarn = self.nfail = 0

    def add(self, av, bv, where, t: Thresholds):
        """Add the compared pixels ``av``, ``bv`` (float64 ``(m, c)``), ``where`` their flat indices."""
        d = np.abs(av - bv)
        aa, bb = np.abs(av), np.abs(bv)
        self.peak = max(self.peak, float(aa.max(initial=0.0)), float(bb.max(initial=0.0)))
        den = aa + bb
        den *= 0.5
        rel = np.divide(d, den, out=np.zeros_like(d), where=den > 0)
        self.n += d.shape[0]
        self.d += d.sum(axis=0)
        self.d2 += np.einsum("ij,ij->j", d, d)
        self.r += rel.sum(axis=0)
        self.r2 += np.einsum("ij,ij->j", rel, rel)
        np.maximum(self.rmax, rel.max(axis=0), out=self.rmax)
        i = np.argmax(d, axis=0)
        top = d[i, np.arange(d.shape[1])]
        better = top > self.dmax  # strictly: the first pixel keeps a tie, as OpenImageIO's scan does
        self.dmax = np.where(better, top, self.dmax)
        self.dat = np.where(better, where[i], self.dat)
        self.nfail += int(_over(d, rel, t.fail, t.fail_relative).sum())
        self.nwarn += int(_over(d, rel, t.warn, t.warn_relative).sum())


def diff_images(a: ArrayLike, b: ArrayLike, *, mask_alpha: bool = True, thresholds: Thresholds | None = None,
                flip: str = "auto") -> DiffReport:
    """Compare ``b`` with ``a`` as OpenImageIO's ``idiff`` does (the module's description gives each figure).

    Works through the image in chunks of :data:`CHUNK` pixels (float64 sums), so memory stays bounded.

    Parameters
    ----------
    a, b : array_like
        Float images ``H x W x C`` (or ``H x W``) of one size, as :func:`lenslab.io.read` gives them.
    mask_alpha : bool
        Compare only the pixels fully covered in both (when either has alpha), colour channels only;
        False compares every pixel and channel, alpha included, as ``idiff`` does.
    thresholds : Thresholds, optional
        ``idiff``'s fail and warn thresholds (default: fail and warn above 1e-6).
    flip : str
        One of :data:`FLIP_MODES`: ``auto`` (HDR-FLIP when either image holds a value above 1, else
        LDR-FLIP), ``hdr``, ``ldr`` or ``off``.

    Returns
    -------
    DiffReport
        Mean, RMS and max errors (with the max's pixel and channel), per-channel figures, PSNR, the
        fail and warn counts, FLIP, and ``verdict`` (:data:`PASS`, :data:`WARNING` or :data:`FAILURE`).

    Raises
    ------
    DiffError
        Images of different sizes or channels, or an unknown FLIP mode.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics.diff import FAILURE, diff_images
    >>> a = np.zeros((2, 3, 3), np.float32)
    >>> b = a.copy(); b[1, 2, 0] = 0.5  # one channel of pixel x=2, y=1
    >>> report = diff_images(a, b, flip="off")
    >>> report.max_error, report.max_at, report.nfail, report.verdict == FAILURE
    (0.5, (2, 1, 'R'), 1, True)
    >>> report.mean_error == 0.5 / 18  # over 6 pixels x 3 channels
    True
    """
    t = thresholds or Thresholds()
    if flip not in FLIP_MODES:
        raise DiffError(f"unknown FLIP mode {flip!r}; choose one of {', '.join(FLIP_MODES)}")
    a, b, names, mask = prepare(a, b, mask_alpha)
    h, w, c = a.shape
    fa, fb, fm = a.reshape(-1, c), b.reshape(-1, c), mask.reshape(-1)
    sums, bad_count, any_big = _Sums(c), 0, False
    keep = np.zeros(h * w, dtype=bool)
    for s0 in range(0, h * w, CHUNK):
        ca = fa[s0:s0 + CHUNK].astype(np.float64)
        cb = fb[s0:s0 + CHUNK].astype(np.float64)
        m = fm[s0:s0 + CHUNK].copy()
        finite = np.isfinite(ca) & np.isfinite(cb)
        if not finite.all():  # a value that is not finite in one image only fails; the same one does not
            same = (ca == cb) | (np.isnan(ca) & np.isnan(cb))
            bad = m & ~np.all(finite | same, axis=-1)
            bad_count += int(bad.sum())
            m &= ~bad
            ca, cb = np.where(finite, ca, 0.0), np.where(finite, cb, 0.0)
        keep[s0:s0 + CHUNK] = m
        any_big = any_big or bool((ca > 1.0).any() or (cb > 1.0).any())
        idx = np.flatnonzero(m)
        if idx.size:
            if idx.size == m.size:
                sums.add(ca, cb, idx + s0, t)
            else:
                sums.add(ca[idx], cb[idx], idx + s0, t)
    n = sums.n
    per = []
    for k, name in enumerate(names):
        if n:
            y, x = divmod(int(sums.dat[k]), w)
            per.append(ChannelStats(name, float(sums.d[k] / n), float(np.sqrt(sums.d2[k] / n)), float(sums.dmax[k]),
                                    (x, y), float(sums.r[k] / n), float(np.sqrt(sums.r2[k] / n)), float(sums.rmax[k])))
        else:
            per.append(ChannelStats(name, math.nan, math.nan, math.nan, None, math.nan, math.nan, math.nan))
    if n:
        mean_error, rms = float(sums.d.sum() / (n * c)), float(np.sqrt(sums.d2.sum() / (n * c)))
        # the overall maximum: the largest channel maximum, the first pixel (then channel) on a tie
        k = min(range(c), key=lambda j: (-sums.dmax[j], sums.dat[j], j))
        max_error = float(sums.dmax[k])
        y, x = divmod(int(sums.dat[k]), w)
        max_at = (x, y, names[k])
        values = ([float(v) for v in a[y, x]], [float(v) for v in b[y, x]])
        psnr = math.inf if rms == 0 else 20.0 * math.log10(sums.peak / rms)
    else:
        mean_error = rms = max_error = psnr = math.nan
        max_at = values = None
    nfail, nwarn = sums.nfail + bad_count, sums.nwarn + bad_count
    compared = n + bad_count
    if bad_count:
        max_error = math.inf
    report = DiffReport(
        width=w, height=h, channels=names, pixels=compared, masked_out=int((~mask).sum()),
        nonfinite=bad_count, mean_error=mean_error, rms_error=rms, psnr=psnr, max_error=max_error,
        max_at=max_at, per_channel=per, nwarn=nwarn, nfail=nfail,
        warn_share=nwarn / compared if compared else math.nan, fail_share=nfail / compared if compared else math.nan,
        flip=None, flip_mode="off", thresholds=t, values_at_max=values)
    if flip != "off" and n:
        mode = flip if flip != "auto" else ("hdr" if any_big else "ldr")
        report.flip, report.flip_mode = flip_error(a, b, keep.reshape(h, w), mode), mode
    report.verdict = verdict(nfail, nwarn, max(compared, 1), max_error, t)
    return report


def flip_error(a: np.ndarray, b: np.ndarray, mask: np.ndarray, mode: str) -> float:
    """Mean FLIP over ``mask`` of the first three channels (one channel repeated): ``mode`` ``hdr`` on the
    linear values, ``ldr`` on their sRGB encodings clipped to [0, 1]. Pixels outside the mask are set to
    0 in both images (FLIP's filters span neighbours)."""
    import flip_evaluator

    def rgb(img):
        img = img[..., :3] if img.shape[2] >= 3 else np.repeat(img[..., :1], 3, axis=-1)
        img = np.where(np.isfinite(img) & mask[..., None], np.maximum(img, 0.0), 0.0)
        if mode == "ldr":
            from lenslab.io.encode import encode_srgb

            img = encode_srgb(np.clip(img, 0.0, 1.0).astype(np.float32))
        return np.ascontiguousarray(img, dtype=np.float32)

    fmap, _, _ = flip_evaluator.evaluate(rgb(a), rgb(b), mode.upper(), inputsRGB=(mode == "ldr"), applyMagma=False,
                                         computeMeanError=False, parameters={})
    fmap = np.asarray(fmap, dtype=np.float64).reshape(mask.shape)
    return float(fmap[mask].mean())


def error_image(a: ArrayLike, b: ArrayLike, *, mask_alpha: bool = True, signed: bool = False,
                scale: float = 1.0) -> np.ndarray:
    """The error map ``|a - b|`` (``a - b`` with ``signed``) times ``scale``, float32.

    Parameters
    ----------
    a, b : array_like
        Float images ``H x W x C`` (or ``H x W``) of one size and channels.
    mask_alpha : bool
        True: RGB (a grey image's error in all three) plus an alpha that is 1 where pixels were compared
        and 0 elsewhere (colour 0 there: premultiplied). False: the error of every channel, in the
        images' own channels (alpha's error in A), as ``idiff -o`` writes it.
    signed : bool
        ``a - b`` instead of its magnitude.
    scale : float
        A factor on the error, to make small differences visible.

    Returns
    -------
    numpy.ndarray
        float32 ``H x W x 4`` (masked) or ``H x W x C``.

    Raises
    ------
    DiffError
        Images of different sizes or channels.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics.diff import error_image
    >>> a = np.ones((1, 2, 3), np.float32)
    >>> b = a.copy(); b[0, 1] = 0.75
    >>> error_image(a, b, signed=True, scale=4.0)[0].tolist()  # (1 - 0.75) x 4, then alpha 1
    [[0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0]]
    """
    a, b, names, mask = prepare(a, b, mask_alpha)
    a, b = a.astype(np.float64), b.astype(np.float64)
    with np.errstate(invalid="ignore"):
        e = (a - b) if signed else np.abs(a - b)
    e = np.where(mask[..., None] & np.isfinite(e), e * scale, 0.0)
    if not mask_alpha:
        return e.astype(np.float32)
    if e.shape[2] == 1:
        e = np.repeat(e, 3, axis=-1)
    return np.concatenate([e[..., :3], mask[..., None].astype(np.float64)], axis=-1).astype(np.float32)


__all__ = ["diff_images", "error_image", "Thresholds", "DiffReport", "DiffError", "relative_error",
           "verdict", "PASS", "WARNING", "FAILURE", "FLIP_MODES"]
