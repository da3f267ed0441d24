"""Masks of the pixels near silhouette and shadow edges, from a renderer's AOVs or from the reference
image itself, so that errors are reported on the edges and away from them; see :mod:`lenslab.metrics`."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from lenslab.metrics.measures import as_image


# -- edges ---------------------------------------------------------------------------------------
def _disk(radius: int) -> np.ndarray:
    k = 2 * int(radius) + 1
    yy, xx = np.mgrid[-radius:radius + 1, -radius:radius + 1]
    return ((xx * xx + yy * yy) <= radius * radius + 0.5).astype(np.uint8).reshape(k, k)


def dilate(mask: ArrayLike, radius: int = 2) -> np.ndarray:
    """Boolean dilation by a disk of ``radius`` pixels (cv2.dilate).

    Parameters
    ----------
    mask : array_like
        Boolean ``H x W``.
    radius : int
        The disk's radius in pixels (0 or less: a copy).

    Returns
    -------
    numpy.ndarray
        bool ``H x W``.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.metrics import dilate
    >>> one = np.zeros((5, 5), bool); one[2, 2] = True
    >>> dilate(one, 1).astype(int).tolist()  # a disk of radius 1: the pixel and its four neighbours
    [[0, 0, 0, 0, 0], [0, 0, 1, 0, 0], [0, 1, 1, 1, 0], [0, 0, 1, 0, 0], [0, 0, 0, 0, 0]]
    """
    import cv2

    m = np.asarray(mask, dtype=bool)
    if radius <= 0:
        return m.copy()
    return cv2.dilate(m.astype(np.uint8), _disk(int(radius)), borderType=cv2.BORDER_CONSTANT,
                      borderValue=0).astype(bool)


def _neighbour_diff(a: np.ndarray, fn) -> np.ndarray:
    """Mark both pixels of every horizontally or vertically adjacent pair where ``fn(p, q)`` is True."""
    out = np.zeros(a.shape[:2], dtype=bool)
    h = fn(a[:, :-1], a[:, 1:])
    out[:, :-1] |= h
    out[:, 1:] |= h
    v = fn(a[:-1, :], a[1:, :])
    out[:-1, :] |= v
    out[1:, :] |= v
    return out


def edge_mask_from_aovs(depth: ArrayLike | None = None, normal: ArrayLike | None = None,
                        prim_id: ArrayLike | None = None, radius: int = 2, depth_tolerance: float = 0.02,
                        normal_tolerance_deg: float = 20.0) -> np.ndarray:
    """Pixels within ``radius`` px of a geometric discontinuity, from the renderer's AOVs.

    Give at least one AOV. Shadow edges are not geometric: combine with :func:`edge_mask_from_image`.

    Parameters
    ----------
    depth : array_like, optional
        ``H x W`` distances, inf or 0 where the ray missed: relative jumps above ``depth_tolerance``
        are silhouettes.
    normal : array_like, optional
        ``H x W x 3`` normals: turning by more than ``normal_tolerance_deg`` between neighbours is a crease.
    prim_id : array_like, optional
        ``H x W`` integers, -1 where the ray missed: neighbours seeing different primitives.
    radius : int
        Pixels marked around each discontinuity.
    depth_tolerance : float
        The relative depth step that counts as a silhouette.
    normal_tolerance_deg : float
        The angle between neighbouring normals that counts as a crease.

    Returns
    -------
    numpy.ndarray
        bool ``H x W``.

    Raises
    ------
    ValueError
        No AOV given.

    Examples
    --------
    A near object (depth 1) in front of a far wall (depth 10), split down the middle:

    >>> import numpy as np
    >>> from lenslab.metrics import edge_mask_from_aovs
    >>> depth = np.full((4, 6), 10.0); depth[:, :3] = 1.0
    >>> edge_mask_from_aovs(depth=depth, radius=0)[0].astype(int).tolist()  # both sides of the step
    [0, 0, 1, 1, 0, 0]
    """
    if depth is None and normal is None and prim_id is None:
        raise ValueError("edge_mask_from_aovs needs depth, normal or prim_id")
    edges = None
    if prim_id is not None:
        pid = np.asarray(prim_id)
        pid = pid[..., 0] if pid.ndim == 3 else pid
        e = _neighbour_diff(pid, lambda p, q: p != q)
        edges = e if edges is None else edges | e
    if depth is not None:
        d = np.asarray(depth, dtype=np.float64)
        d = d[..., 0] if d.ndim == 3 else d
        hit = np.isfinite(d) & (d > 0)
        dd = np.where(hit, d, 0.0)

        def jump(p, q):
            ph, qh = p > 0, q > 0
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.abs(p - q) / np.maximum(np.minimum(p, q), 1e-12)
            return (ph != qh) | (ph & qh & (rel > depth_tolerance))

        e = _neighbour_diff(dd, jump)
        edges = e if edges is None else edges | e
    if normal is not None:
        n = np.asarray(normal, dtype=np.float64)
        cos_tol = math.cos(math.radians(normal_tolerance_deg))
        e = _neighbour_diff(n, lambda p, q: np.einsum("...i,...i->...", p, q) < cos_tol * (
            np.linalg.norm(p, axis=-1) * np.linalg.norm(q, axis=-1)))
        edges = e if edges is None else edges | e
    return dilate(edges, radius)


def edge_mask_from_image(image: ArrayLike, radius: int = 2, threshold: float = 0.25, denoise: bool = True,
                         mask: ArrayLike | None = None) -> np.ndarray:
    """Pixels within ``radius`` px of a strong edge of the image's log luminance.

    The log luminance (Rec.709 weights, floored at 1e-3 of its mean) is denoised with an edge-preserving
    bilateral filter when ``denoise`` is set (Monte Carlo noise would otherwise read as edges), then an
    edge is a pixel whose central-difference gradient magnitude exceeds ``threshold`` (in natural-log
    units per pixel: 0.25 is a 28% step between neighbours). Pixels outside ``mask`` (e.g. alpha < 1)
    and their boundary count as edges, since the rim of a lens is a silhouette too.

    Parameters
    ----------
    image : array_like
        Linear ``H x W x C`` or ``H x W``.
    radius : int
        Pixels marked around each edge.
    threshold : float
        The gradient of the log luminance, per pixel, that makes an edge.
    denoise : bool
        Smooth the log luminance first (bilateral filter), for a noisy traced image.
    mask : array_like, optional
        Boolean ``H x W`` of the pixels that hold the image (alpha = 1).

    Returns
    -------
    numpy.ndarray
        bool ``H x W``.

    Examples
    --------
    A step from 1 to 4 (a log step of 1.39, split over two central differences) is an edge; a smooth
    ramp of 1% per pixel is not:

    >>> import numpy as np
    >>> from lenslab.metrics import edge_mask_from_image
    >>> step = np.ones((4, 8)); step[:, 4:] = 4.0
    >>> edge_mask_from_image(step, radius=0, denoise=False)[0].astype(int).tolist()
    [0, 0, 0, 1, 1, 0, 0, 0]
    >>> bool(edge_mask_from_image(np.geomspace(1.0, 1.07, 8)[None].repeat(4, 0), radius=0).any())
    False
    """
    import cv2

    img = as_image(image, "image").astype(np.float64, copy=False)
    if img.shape[-1] >= 3:
        lum = img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722
    else:
        lum = img[..., 0]
    lum = np.where(np.isfinite(lum), np.maximum(lum, 0.0), 0.0)
    mean = float(lum.mean()) if lum.size else 0.0
    eps = 1e-3 * mean if mean > 0 else 1e-6
    log = np.log(lum + eps).astype(np.float32)
    if denoise:
        log = cv2.bilateralFilter(log, d=5, sigmaColor=0.3, sigmaSpace=1.5)
    gy, gx = np.gradient(log.astype(np.float64))
    edges = np.hypot(gx, gy) > threshold
    if mask is not None:
        m = np.asarray(mask, dtype=bool)
        edges |= ~m
    return dilate(edges, radius)
