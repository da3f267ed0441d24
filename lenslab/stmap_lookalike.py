"""Whether an image looks like an ST map (one made by another tool carries no ``lenslab:stmap`` mark): ``lenslab
info`` says so, with how to use it, without changing how the file is read.

An image looks like an ST map when it has two to four channels, the first two named as a map's coordinates are
(``s, t``, ``u, v`` or ``R, G``: Nuke's STMap, a UV pass, ffmpeg's or OpenCV's colour channels), and, over the
pixels that count (the fourth channel above 1/2 where there is one, else every pixel), both coordinates are
finite and within [0, 1], the first never falls along a row (left to right) and the second changes one way only
down each column, each spanning at least a tenth of [0, 1] across the image. A gradient test pattern of the same
shape is one too: the note then says "looks like".
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

#: the names of a map's two coordinate channels (lower case) that ``info`` recognises
PAIRS = (("s", "t"), ("u", "v"), ("r", "g"))
#: a coordinate spans at least this much of [0, 1] over the image
MIN_SPAN = 0.1
#: float rounding of values that are meant to be equal (16-bit codes differ by 1/65535 at least)
TIE = 1e-7
#: rows looked at at once (a large picture is gone through in bands, never copied whole)
BAND_ROWS = 256


def looks_like_st_map(image: np.ndarray, channels: Sequence[str]) -> bool:
    """True when ``image`` (``H x W x C`` float, as read) with channel names ``channels`` has the shape and values
    of an ST map (see the module's text).

    >>> h, w = 4, 6
    >>> y, x = np.mgrid[0:h, 0:w] + 0.5
    >>> looks_like_st_map(np.stack([x / w, 1 - y / h], -1), ["s", "t"])
    True
    >>> looks_like_st_map(np.stack([x / w, y / h * (x % 2)], -1), ["R", "G"])
    False
    """
    return st_map_way(image, channels) is not None


def st_map_way(image: np.ndarray, channels: Sequence[str]) -> int | None:
    """How the second coordinate of an image that looks like an ST map goes down each column: -1 falling, as Nuke's
    ``t = 1 - y / H`` does, +1 growing (``y / H``: a remap grid normalised as OpenCV counts rows, which ``--stmap``
    would read upside down); None when the image does not look like an ST map.

    >>> h, w = 4, 6
    >>> y, x = np.mgrid[0:h, 0:w] + 0.5
    >>> st_map_way(np.stack([x / w, 1 - y / h], -1), ["s", "t"]), st_map_way(np.stack([x / w, y / h], -1), ["R", "G"])
    (-1, 1)
    """
    if image.ndim != 3 or not 2 <= image.shape[2] <= 4 or min(image.shape[:2]) < 2 or len(channels) < 2:
        return None
    names = tuple(str(c).rsplit(".", 1)[-1].lower() for c in channels[:2])
    if names not in PAIRS:
        return None
    s, t = image[..., 0], image[..., 1]  # (views: a large picture is not copied)
    alpha = image[..., 3] if image.shape[2] == 4 else None
    if not _lines_agree(s, t, alpha):  # a picture fails on three rows and columns: the whole is not gone through
        return None
    lo, hi = [np.inf, np.inf], [-np.inf, -np.inf]
    falls, down, seen = False, set(), 0
    for r0 in range(0, s.shape[0], BAND_ROWS):  # bands overlapping by a row, so every pair down a column is seen
        r1 = min(s.shape[0], r0 + BAND_ROWS + 1)
        bs, bt = s[r0:r1].astype(np.float64), t[r0:r1].astype(np.float64)
        ok = np.ones(bs.shape, dtype=bool) if alpha is None else alpha[r0:r1] > 0.5
        rows = slice(0, r1 - r0 - (r1 < s.shape[0]))  # the band's own rows (the last one is the next band's first)
        with np.errstate(invalid="ignore"):
            for k, v in enumerate((bs[rows][ok[rows]], bt[rows][ok[rows]])):
                if v.size and not np.isfinite(v).all():
                    return None
                if v.size:
                    lo[k], hi[k] = min(lo[k], v.min()), max(hi[k], v.max())
            seen += int(ok[rows].sum())
            ds = np.diff(bs, axis=1)[ok[:, 1:] & ok[:, :-1]]
            dt = np.diff(bt, axis=0)[ok[1:] & ok[:-1]]
        falls |= bool((ds < -TIE).any())
        down |= {1} if (dt > TIE).any() else set()
        down |= {-1} if (dt < -TIE).any() else set()
        if falls or len(down) > 1 or lo[0] < 0 or lo[1] < 0 or hi[0] > 1 or hi[1] > 1:
            return None
    if seen >= 4 and hi[0] - lo[0] >= MIN_SPAN and hi[1] - lo[1] >= MIN_SPAN and down:
        return down.pop()
    return None


def _lines_agree(s: np.ndarray, t: np.ndarray, alpha: np.ndarray | None) -> bool:
    """Whether ``s`` never falls along the first, middle and last rows and ``t`` changes one way only down the
    first, middle and last columns (their valid pairs): what :func:`looks_like_st_map` asks of every row and column."""
    h, w = s.shape
    way = set()
    for k in sorted({0, h // 2, h - 1}):
        ok = np.ones(w - 1, dtype=bool) if alpha is None else (alpha[k, 1:] > 0.5) & (alpha[k, :-1] > 0.5)
        with np.errstate(invalid="ignore"):
            if (np.diff(s[k].astype(np.float64))[ok] < -TIE).any():
                return False
    for k in sorted({0, w // 2, w - 1}):
        ok = np.ones(h - 1, dtype=bool) if alpha is None else (alpha[1:, k] > 0.5) & (alpha[:-1, k] > 0.5)
        with np.errstate(invalid="ignore"):
            d = np.diff(t[:, k].astype(np.float64))[ok]
        way |= ({1} if (d > TIE).any() else set()) | ({-1} if (d < -TIE).any() else set())
    return len(way) <= 1


__all__ = ["looks_like_st_map", "st_map_way"]
