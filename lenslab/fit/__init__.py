"""Fitting with nlopt: lens to lens, calibration from points, auto-scale for warps, tone-curve matching.

- :func:`fit_lens`: the parameters of one lens model that best reproduce another over an image;
- :func:`fit_points`: a lens (and optionally its pose) from measured pixel <-> direction pairs, robustly;
- :func:`autoscale`: the output field of view at which a warp has no invalid pixel (or shows all the source);
- :func:`fit_tone`: exposure and tone-curve parameters that make an HDR image reproduce a given LDR one;
- :func:`minimize`: the nlopt driver all of them share.
"""

from __future__ import annotations

from lenslab.fit.autoscale import AutoscaleResult, autoscale
from lenslab.fit.lens import LensFit, fit_lens
from lenslab.fit.optimize import OptimizeResult, minimize
from lenslab.fit.points import PointSet, PointsFit, fit_points, read_points
from lenslab.fit.tone import ToneFit, fit_tone

__all__ = [
    "OptimizeResult", "minimize", "LensFit", "fit_lens", "PointSet", "PointsFit", "fit_points", "read_points",
    "AutoscaleResult", "autoscale", "ToneFit", "fit_tone",
]
