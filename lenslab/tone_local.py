"""OpenCV's local tone-mapping operators (Drago, Mantiuk) behind ``lenslab.tone``'s curve interface.

These are not per-pixel curves: each pixel's result depends on the whole image. OpenCV first divides
the image by its maximum and floors luminance at 1e-4 of it before taking logarithms, so a sun of
30000 over a scene near 1 would sit the whole scene on that floor. Before handing the image over, lenslab
therefore clips it at ``2**headroom`` times its log-average luminance (positive pixels, darkest and
brightest percent left out); whatever lies above is white in the result anyway. OpenCV's own gamma
is left at 1 (the output is display-linear: lenslab's writer applies the sRGB encoding) and its
output, stretched by OpenCV to [0, 1], is cleaned of the NaN it can leave (and then stretched again).
OpenCV weighs luminance with Rec.601 luma (0.299, 0.587, 0.114) internally.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import ToneError

_MIN_SIDE = {"drago": 1, "mantiuk": 4}


def _quietly(fn, *args):
    """Call ``fn`` with OpenCV's notices about its own internals (not about the image) silenced."""
    import cv2

    logging = getattr(getattr(cv2, "utils", None), "logging", None)
    if logging is None:  # pragma: no cover - builds without the logging module
        return fn(*args)
    level = logging.getLogLevel()
    logging.setLogLevel(logging.LOG_LEVEL_ERROR)
    try:
        return fn(*args)
    finally:
        logging.setLogLevel(level)


def apply(name: str, image: np.ndarray, params: dict, weights) -> np.ndarray:
    """Run the OpenCV operator ``name`` on a repaired, exposed float32 image; float32, same shape."""
    import cv2

    from lenslab.tone import _luminance_sample, log_average

    x = np.asarray(image, dtype=np.float32)
    shape = x.shape
    grey = not (x.ndim == 3 and x.shape[-1] == 3)
    if x.ndim == 3:
        img = x if not grey else np.repeat(x[..., :1], 3, axis=-1)
    elif x.ndim == 2:
        img = np.repeat(x[..., None], 3, axis=-1)
    else:
        img = np.repeat(x.reshape(1, -1, 1), 3, axis=-1)
    h, w = img.shape[:2]
    if min(h, w) < _MIN_SIDE[name]:
        raise ToneError(f"curve {name!r} needs an image at least {_MIN_SIDE[name]} pixels on each side "
                        f"(got {w} x {h}); use a per-pixel curve for tiny images")
    img = np.ascontiguousarray(img, dtype=np.float32)
    avg = log_average(_luminance_sample(img, weights), trim=1.0)
    if avg <= 0:
        return np.zeros(shape, np.float32)  # nothing positive: black stays black
    img = np.minimum(img, np.float32(avg * 2.0 ** params["headroom"]))

    if name == "drago":
        op = cv2.createTonemapDrago(gamma=1.0, saturation=float(params["saturation"]), bias=float(params["bias"]))
    elif name == "mantiuk":
        op = cv2.createTonemapMantiuk(gamma=1.0, scale=float(params["scale"]),
                                      saturation=float(params["saturation"]))
    else:  # pragma: no cover - the registry only routes these two here
        raise ToneError(f"no OpenCV operator called {name!r}")
    out = _quietly(op.process, img)
    bad = ~np.isfinite(out)
    if bad.any():
        # OpenCV leaves NaN where it divides 0 by 0, and a NaN spoils its final stretch to [0, 1]:
        # set them to 0 and redo that stretch
        out[bad] = 0.0
        lo, hi = float(out.min()), float(out.max())
        if hi > lo:
            out = (out - np.float32(lo)) / np.float32(hi - lo)
    np.clip(out, 0.0, 1.0, out=out)
    if grey:
        out = out.mean(axis=-1, dtype=np.float32)
    return np.ascontiguousarray(out, dtype=np.float32).reshape(shape)
