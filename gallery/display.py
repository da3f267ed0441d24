"""Turning HDR images into the display images of the page: tone mapping, downsizing, difference maps.

Pure functions, float32 arrays in and out. Display images are display-linear in [0, 1] (``lenslab.io.write``
applies the sRGB encoding); difference maps are colour-mapped and already display-encoded.
"""

from __future__ import annotations

import numpy as np

#: Invalid pixels of a difference map (outside a lens's image circle, or not covered): a neutral grey.
INVALID_GREY = 0.2

#: Full scale of difference maps: a pixel whose mean absolute difference equals this fraction of the
#: reference's mean radiance is shown at the top of the colour map.
DIFF_SCALE = 0.25

DIFF_COLORMAP = "inferno"


def split_alpha(image: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Colour (``H x W x 3`` float32) and alpha (``H x W`` or None) of a 1-, 3- or 4-channel image."""
    a = np.asarray(image, dtype=np.float32)
    if a.ndim == 2:
        a = a[..., None]
    channels = a.shape[-1]
    if channels == 1:
        return np.repeat(a, 3, axis=-1), None
    if channels == 2:  # grey + alpha
        return np.repeat(a[..., :1], 3, axis=-1), a[..., 1]
    if channels == 3:
        return a, None
    return a[..., :3], a[..., 3]


def tone(image: np.ndarray, curve: str = "hable", exposure: float = 0.0) -> np.ndarray:
    """Display-linear RGB in [0, 1] (float32). Colour is premultiplied by alpha, so this is the image over black."""
    from lenslab.tone import tonemap
    from lenslab.tone.registry import get_curve

    rgb, _ = split_alpha(image)
    if get_curve(curve).ignores_exposure:  # the page's exposure means nothing to it (mantiuk): no note for it
        exposure = 0.0
    return np.clip(np.asarray(tonemap(rgb, curve=curve, exposure=exposure), dtype=np.float32), 0.0, 1.0)


#: the page's card colour (style.css ``--card``, #1f2226), linear: where a lens sees nothing its picture
#: shows the card, so each picture has the shape of its lens (a fisheye's disc, an ellipse), not a black box
CARD_LINEAR = (0.01370, 0.01600, 0.01938)


def over_card(shown: np.ndarray, alpha: np.ndarray | None) -> np.ndarray:
    """Display-linear premultiplied colour over the card's colour, by ``alpha`` (None: fully covered)."""
    if alpha is None:
        return shown
    return shown + (1.0 - np.clip(alpha, 0.0, 1.0))[..., None] * np.asarray(CARD_LINEAR, np.float32)


def fit_within(image: np.ndarray, max_side: int) -> np.ndarray:
    """Shrink (area-averaged, aspect kept) so that neither side exceeds ``max_side``; never enlarge."""
    import cv2

    h, w = image.shape[:2]
    scale = max_side / max(h, w)
    if scale >= 1.0:
        return image
    size = (max(1, round(w * scale)), max(1, round(h * scale)))
    out = cv2.resize(np.ascontiguousarray(image), size, interpolation=cv2.INTER_AREA)
    return out.reshape(size[1], size[0], *image.shape[2:])


def valid_mask(*alphas: np.ndarray | None, threshold: float = 0.999) -> np.ndarray | None:
    """Pixels fully covered in every image that has an alpha (None when none has)."""
    mask = None
    for a in alphas:
        if a is None:
            continue
        m = a >= threshold
        mask = m if mask is None else mask & m
    return mask


def difference(test: np.ndarray, reference: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Per-pixel difference normalised by the reference's mean radiance.

    ``d(p) = mean_c |test - reference| / mean(reference)`` over the pixels covered in both images.
    Its mean over those pixels is the relative L1 error of the whole image, so the map shows where the
    error of the card's figure comes from. Returns ``(d (H x W float32), valid (H x W bool), mean of d)``.
    """
    t, ta = split_alpha(test)
    r, ra = split_alpha(reference)
    if t.shape != r.shape:
        raise ValueError(f"difference of images of different sizes: {t.shape[:2]} and {r.shape[:2]}")
    valid = valid_mask(ta, ra)
    if valid is None:
        valid = np.ones(t.shape[:2], dtype=bool)
    valid &= np.all(np.isfinite(t), axis=-1) & np.all(np.isfinite(r), axis=-1)
    abs_diff = np.abs(t - r).mean(axis=-1, dtype=np.float64)
    ref_mean = float(np.abs(r[valid]).mean()) if valid.any() else 0.0
    d = np.zeros(t.shape[:2], dtype=np.float32)
    if ref_mean > 0:
        d[valid] = (abs_diff[valid] / ref_mean).astype(np.float32)
    mean = float(d[valid].mean()) if valid.any() else 0.0
    return d, valid, mean


def colour_map(values: np.ndarray, valid: np.ndarray | None = None, scale: float = DIFF_SCALE,
               colormap: str = DIFF_COLORMAP) -> np.ndarray:
    """Colour-mapped ``values / scale`` (display-encoded RGB float32 in [0, 1]); invalid pixels grey."""
    import matplotlib

    cmap = matplotlib.colormaps[colormap]
    x = np.clip(np.asarray(values, dtype=np.float64) / scale, 0.0, 1.0)
    rgb = cmap(x)[..., :3].astype(np.float32)
    if valid is not None:
        rgb[~valid] = INVALID_GREY
    return rgb


def legend_gradient(colormap: str = DIFF_COLORMAP, stops: int = 9) -> str:
    """A CSS ``linear-gradient`` of the colour map, for the legend under difference maps."""
    import matplotlib

    cmap = matplotlib.colormaps[colormap]
    parts = []
    for i in range(stops):
        r, g, b, _ = cmap(i / (stops - 1))
        parts.append(f"rgb({round(r * 255)},{round(g * 255)},{round(b * 255)}) {100 * i / (stops - 1):.0f}%")
    return "linear-gradient(to right, " + ", ".join(parts) + ")"
