"""Tone curves: scene-linear HDR values -> display-linear values in [0, 1].

``tonemap(image, curve="hable", exposure=0.0, mode="per-channel", **params)`` is the one entry point
the rest of lenslab uses (:mod:`lenslab.tone.mapping` says the order of work: repair, exposure, curve,
per channel or on luminance). It returns display-linear float32; ``lenslab.io.write`` encodes.

Every curve lives in :data:`CURVES` (name -> :class:`Curve`, :mod:`lenslab.tone.registry`) with its
declared parameters (:class:`lenslab.params.Param`), ranges and defaults; an unknown name or a
parameter out of range raises :class:`lenslab.errors.ToneError` listing what is valid. One module per
curve family holds the formula, its published source and a doctest:

- :mod:`~lenslab.tone.gamma`: ``clamp``, ``gamma``
- :mod:`~lenslab.tone.reinhard`: ``reinhard``, ``reinhard-extended``, ``reinhard2002`` (Reinhard et al. 2002)
- :mod:`~lenslab.tone.hable`: ``hable`` (Hable 2010, blog and GDC constants)
- :mod:`~lenslab.tone.aces`: ``aces`` (Narkowicz 2016); :mod:`~lenslab.tone.aces_hill`: ``aces-hill`` (Hill 2016)
- :mod:`~lenslab.tone.agx`: ``agx`` (Sobotka, Wrensch 2024); :mod:`~lenslab.tone.pbr_neutral`: ``pbr-neutral`` (Khronos 2024)
- :mod:`~lenslab.tone.local`: ``drago``, ``mantiuk`` (OpenCV's local operators)

Exposure and auto-exposure are in :mod:`~lenslab.tone.exposure`, the block sweep in
:mod:`~lenslab.tone.sweep`, the kernels' building blocks in :mod:`~lenslab.tone.kernels`, the chart
in :mod:`~lenslab.tone.plot`. The closed-form curves are also functions (``hable(x, **params)`` ...)
that take any float array and return float32 of the same shape.
"""

from __future__ import annotations

from lenslab.params import Param
from lenslab.tone.exposure import EXPOSURE_RANGE, MIDDLE_GREY, auto_exposure, log_average, luminance_weights
from lenslab.tone.mapping import ExposureIgnoredWarning, ToneWarning, tonemap
from lenslab.tone.registry import CURVES, Curve, curve_names, describe_curves, get_curve

# the curve modules register themselves, in the order users see them listed
from lenslab.tone.gamma import clamp, gamma  # isort: skip
from lenslab.tone.reinhard import reinhard, reinhard2002, reinhard_extended  # isort: skip
from lenslab.tone.hable import HABLE_PRESETS, hable  # isort: skip
from lenslab.tone.aces import aces  # isort: skip
from lenslab.tone.aces_hill import ACES_HILL_INPUT, ACES_HILL_OUTPUT, aces_hill  # isort: skip
from lenslab.tone.agx import AGX_INSET, AGX_MAX_EV, AGX_MIN_EV, AGX_OUTSET, AGX_POLY, agx  # isort: skip
from lenslab.tone.pbr_neutral import pbr_neutral  # isort: skip
from lenslab.tone.local import drago, mantiuk  # isort: skip

__all__ = [
    "CURVES", "Curve", "Param", "ToneWarning", "ExposureIgnoredWarning", "tonemap", "auto_exposure", "log_average",
    "luminance_weights", "curve_names", "get_curve", "describe_curves",
    "clamp", "gamma", "reinhard", "reinhard_extended", "reinhard2002", "hable", "aces", "aces_hill",
    "agx", "pbr_neutral", "drago", "mantiuk",
    "HABLE_PRESETS", "EXPOSURE_RANGE", "MIDDLE_GREY",
    "ACES_HILL_INPUT", "ACES_HILL_OUTPUT", "AGX_INSET", "AGX_OUTSET", "AGX_MIN_EV", "AGX_MAX_EV", "AGX_POLY",
]
