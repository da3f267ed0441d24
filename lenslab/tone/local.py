"""OpenCV's local tone-mapping operators (Drago, Mantiuk) as curves of ``lenslab.tone``.

These are not per-pixel curves: each pixel's result depends on the whole image. OpenCV first divides
the image by its maximum and floors luminance at 1e-4 of it before taking logarithms, so a sun of
30000 over a scene near 1 would sit the whole scene on that floor. Before handing the image over, lenslab
therefore clips it at ``2**headroom`` times its log-average luminance (positive pixels, darkest and
brightest percent left out); whatever lies above is white in the result anyway. OpenCV's own gamma
is left at 1 (the output is display-linear: lenslab's writer applies the sRGB encoding).

Drago's output, stretched by OpenCV to [0, 1], is cleaned of the NaN it can leave (and then stretched
again). Mantiuk keeps OpenCV's reconstruction of the luminance but not its ending: OpenCV stretches the
result's maximum to 1, so a sun set the white and left a panorama murky (median code 33 of 255);
lenslab puts the result on the display as Mantiuk's reference implementation does (:func:`display_map`),
and clips the scene so that OpenCV's floor lies below its darkest 0.1 percent. OpenCV weighs luminance
with Rec.601 luma (0.299, 0.587, 0.114) internally. An image of one luminance has no contrast for Mantiuk
to map (OpenCV's solver fails on it): it maps to mid-grey, colour kept as Mantiuk keeps it, so a flat
image gives a flat image.

>>> ramp = np.repeat(np.geomspace(0.01, 100.0, 16, dtype=np.float32)[None, :, None], 3, axis=2)
>>> y = drago(np.repeat(ramp, 4, axis=0))[0, :, 0]
>>> bool(np.all(np.diff(y) > 0)), float(y[-1])              # OpenCV stretches the result to [0, 1]
(True, 1.0)
>>> y = mantiuk(np.repeat(ramp, 4, axis=0))
>>> bool(y.min() >= 0.0), float(y.max())                      # its 99.9th percentile at 1
(True, 1.0)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import ToneError
from lenslab.params import Param
from lenslab.tone.exposure import log_average, luminance_sample
from lenslab.tone.mapping import tonemap
from lenslab.tone.registry import register

_MIN_SIDE = {"drago": 1, "mantiuk": 4}
_REC601 = (0.299, 0.587, 0.114)  # OpenCV's luma weights (COLOR_RGB2GRAY)
_OPENCV_FLOOR = 1e-4  # OpenCV's Mantiuk floors luminance at this fraction of its maximum
#: Mantiuk's reference implementation (pfstmo mantiuk06): display range in log10 units, percent cut at each end
DISPLAY_RANGE = 2.3
CUT_PERCENT = 0.1


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


def _apply(name: str, image: np.ndarray, params: dict, weights) -> np.ndarray:
    """Run the OpenCV operator ``name`` on a repaired, exposed float32 image; float32, same shape."""
    import cv2

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
    avg = log_average(luminance_sample(img, weights), trim=1.0)
    if avg <= 0:
        return np.zeros(shape, np.float32)  # nothing positive: black stays black
    if name == "mantiuk":
        out = _mantiuk(img, avg, params)
        return (out.mean(axis=-1, dtype=np.float32) if grey else out).reshape(shape)
    img = np.minimum(img, np.float32(avg * 2.0 ** params["headroom"]))

    if name != "drago":  # pragma: no cover - the registry only routes these two here
        raise ToneError(f"no OpenCV operator called {name!r}")
    op = cv2.createTonemapDrago(gamma=1.0, saturation=float(params["saturation"]), bias=float(params["bias"]))
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


def _mantiuk(img: np.ndarray, avg: float, params: dict) -> np.ndarray:
    """Mantiuk contrast mapping of a repaired, exposed float32 H x W x 3 image (log-average ``avg`` > 0):
    OpenCV's reconstruction of the luminance, then the authors' display mapping (:func:`display_map`),
    then the colour of each pixel as Mantiuk keeps it, ``(c / L)^saturation`` times the new luminance."""
    import cv2

    luma = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)  # Rec.601 luma, as OpenCV's operator takes it
    if float(luma.max()) == float(luma.min()):
        return _no_contrast(img, luma, float(params["saturation"]))
    positive = luma[luma > 0]
    if positive.size == 0:  # pragma: no cover - avg > 0 means some pixel is positive
        return np.zeros_like(img)
    # OpenCV floors luminance at 1e-4 of the maximum it is given (13.3 stops): the top is chosen so that the
    # darkest 0.1 percent of the scene stays above that floor (what lies above the top is white anyway),
    # but at least 4 stops and at most `headroom` stops above the log-average
    dark = float(np.percentile(positive, CUT_PERCENT))
    top = min(float(luma.max()), avg * 2.0 ** params["headroom"], max(dark / _OPENCV_FLOOR, avg * 16.0))
    lum = np.clip(luma, np.float32(top * _OPENCV_FLOOR), np.float32(top))
    # OpenCV's operator on a probe whose green is 0 and whose red and blue are the luminance over their
    # luma weights: its luma is the luminance, its minimum 0, so OpenCV's final stretch (minimum to 0,
    # maximum to 1) is a plain division by the maximum and its red channel is the new luminance, scaled
    k = np.float32(1.0 / (_REC601[0] + _REC601[2]))
    probe = np.zeros_like(img)
    probe[..., 0] = lum * k
    probe[..., 2] = lum * k
    op = cv2.createTonemapMantiuk(gamma=1.0, scale=_OPENCV_SCALE, saturation=1.0)
    new = _quietly(op.process, probe)[..., 0]
    shown = display_map(np.log(np.maximum(new, np.finfo(np.float32).tiny)), float(params["display_range"]))
    ratio = np.divide(img, luma[..., None], out=np.zeros_like(img), where=luma[..., None] > 0)
    out = np.power(ratio, np.float32(params["saturation"]), dtype=np.float32) * shown[..., None]
    return np.clip(np.nan_to_num(out, nan=0.0, posinf=1.0), 0.0, 1.0).astype(np.float32)


def display_map(log_lum: np.ndarray, display_range: float = DISPLAY_RANGE) -> np.ndarray:
    """The display mapping of Mantiuk's reference implementation (pfstmo ``mantiuk06``): the 0.1th and 99.9th
    percentiles of the reconstructed log10 luminance go to ``-display_range`` and 0 (2.3 log10 units: a
    200:1 display), linearly in log; what lies beyond is clipped to [0, 1].

    ``log_lum``: natural-log luminance, any scale (only its percentiles matter). Returns float32
    display-linear luminance, ``10 ** ((y - y_lo) / (y_hi - y_lo) * display_range - display_range)``.

    >>> y = display_map(np.log(np.geomspace(1e-3, 1e3, 1001)))
    >>> [round(float(v), 4) for v in (y[0], y[500], y[-1])]   # 0.1 % cut at each end
    [0.005, 0.0708, 1.0]
    """
    y = np.asarray(log_lum, dtype=np.float64) / np.log(10.0)
    lo, hi = np.percentile(y, [CUT_PERCENT, 100.0 - CUT_PERCENT])
    if not hi > lo:  # pragma: no cover - an image of one luminance goes to _no_contrast
        return np.full(y.shape, 10.0 ** (-0.5 * display_range), np.float32)
    out = np.power(10.0, (y - lo) / (hi - lo) * display_range - display_range)
    return np.clip(out, 0.0, 1.0).astype(np.float32)


def _no_contrast(img: np.ndarray, luma: np.ndarray, saturation: float) -> np.ndarray:
    """Mantiuk on an image of one luminance (a flat image): there is no contrast to map (OpenCV's solver
    fails on it), so the luminance goes to mid-grey 0.5 and colour follows as OpenCV's Mantiuk maps it,
    ``(c / L)^saturation * 0.5``, clipped to [0, 1]: a flat image gives a flat image."""
    lum = np.maximum(luma[..., None], np.float32(1e-30))
    out = np.float32(0.5) * np.power(img / lum, np.float32(saturation), dtype=np.float32)
    return np.clip(out, 0.0, 1.0).astype(np.float32)


_LOCAL_HEADROOM = Param("headroom", 12.0, "how far above the log-average the image is kept before OpenCV's "
                        "normalisation by the maximum (brighter is clipped)", 1.0, 30.0, units="stops")


_DRAGO_P = (Param("saturation", 1.0, "colour saturation (OpenCV)", 0.0, 4.0, lo_open=True),
            Param("bias", 0.85, "bias of the logarithmic base (Drago: 0.7 to 0.9)", 0.0, 1.0, lo_open=True),
            _LOCAL_HEADROOM)
#: OpenCV's contrast factor: with the paper's power-law transducer it scales every contrast alike, so the
#: rebuilt luminance is a power of the scene's, and the display mapping takes any power to the same image
_OPENCV_SCALE = 0.7
_MANTIUK_P = (Param("saturation", 1.0, "colour saturation (OpenCV)", 0.0, 4.0, lo_open=True),
              _LOCAL_HEADROOM,
              Param("display_range", DISPLAY_RANGE, "display dynamic range the scene's 0.1 to 99.9 percentiles "
                    "are mapped to (2.3: 200:1, Mantiuk's reference implementation)", 0.5, 6.0,
                    units="log10 units"))


@register("drago", "local", _DRAGO_P, build=lambda image, p, w: _apply("drago", image, p, w))
def drago(rgb: ArrayLike, saturation: float = 1.0, bias: float = 0.85, headroom: float = 12.0) -> np.ndarray:
    """Drago adaptive logarithmic mapping (OpenCV ``createTonemapDrago``):
    Ld = log(L + 1) / log(2 + 8 (L / Lmax)^(log(bias) / log(0.5))), L relative to the log-average.

    Drago, Myszkowski, Annen, Chiba, "Adaptive Logarithmic Mapping For Displaying High Contrast
    Scenes", Eurographics 2003. Not a per-pixel curve: it depends on the image's maximum and average.

    Parameters
    ----------
    rgb : array_like
        Scene-linear RGB, ``H x W x 3``.
    saturation : float
        OpenCV's colour saturation (1 keeps it).
    bias : float
        Drago's bias, in (0, 1]: lower gives more contrast in the highlights.
    headroom : float
        Stops kept above the log-average before OpenCV sees the image (its float input is bounded).

    Returns
    -------
    numpy.ndarray
        float32 display-linear RGB in [0, 1], ``H x W x 3``.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.tone import drago
    >>> image = np.geomspace(0.01, 100.0, 64 * 3, dtype=np.float32).reshape(8, 8, 3)
    >>> out = drago(image)
    >>> out.shape, out.dtype, bool(out.min() >= 0.0 and out.max() <= 1.0)
    ((8, 8, 3), dtype('float32'), True)
    >>> bool(np.all(np.diff(out.reshape(-1, 3).mean(axis=1)) >= 0))  # brighter in, brighter out
    True
    """
    return tonemap(rgb, "drago", saturation=saturation, bias=bias, headroom=headroom)


@register("mantiuk", "local", _MANTIUK_P, build=lambda image, p, w: _apply("mantiuk", image, p, w),
          ignores_exposure="it puts the scene's 0.1 to 99.9 percentiles on the display whatever the exposure")
def mantiuk(rgb: ArrayLike, saturation: float = 1.0, headroom: float = 12.0,
            display_range: float = DISPLAY_RANGE) -> np.ndarray:
    """Mantiuk contrast-domain mapping: contrasts of the log luminance pyramid are scaled (OpenCV
    ``createTonemapMantiuk``), the luminance is rebuilt by conjugate gradients, and its 0.1 to 99.9
    percentiles are put on a 200:1 display as the authors' implementation (pfstmo) does.

    Mantiuk, Myszkowski, Seidel, "A Perceptual Framework for Contrast Processing of High Dynamic
    Range Images", ACM TAP 2006. A local operator: not a per-pixel curve. OpenCV maps each contrast
    through the paper's transducer ``T(G) = 54.09288 G^0.4185``, scales the response by its ``scale`` and
    maps it back, so each contrast is multiplied by ``scale^(1 / 0.4185)`` alike: the rebuilt luminance is
    a power of the scene's, which the display mapping takes to the same image for any ``scale`` (so it is
    not a parameter here; ``display_range`` sets the contrast). OpenCV's own ending (the maximum to 1, a linear stretch) is replaced by :func:`display_map`: with it a sun set
    the white point and left the scene dark.

    Parameters
    ----------
    rgb : array_like
        Scene-linear RGB, ``H x W x 3``.
    saturation : float
        Colour saturation: ``(c / L)^saturation`` times the new luminance (1 keeps it).
    headroom : float
        Stops kept above the log-average at most before OpenCV sees the image (its float input is bounded).
    display_range : float
        The display's dynamic range in log10 units that the scene's 0.1 to 99.9 percentiles fill.

    Returns
    -------
    numpy.ndarray
        float32 display-linear RGB in [0, 1], ``H x W x 3``.

    Examples
    --------
    >>> import numpy as np
    >>> from lenslab.tone import mantiuk
    >>> image = np.geomspace(0.01, 100.0, 16 * 16 * 3, dtype=np.float32).reshape(16, 16, 3)
    >>> out = mantiuk(image)
    >>> out.shape, out.dtype, bool(out.min() >= 0.0 and out.max() <= 1.0)
    ((16, 16, 3), dtype('float32'), True)
    >>> bool(out[-1].mean() > out[0].mean())  # the bright end stays brighter than the dark one
    True
    """
    return tonemap(rgb, "mantiuk", saturation=saturation, headroom=headroom, display_range=display_range)
