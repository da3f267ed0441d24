"""The tone-curve chart: every curve (or a chosen few) on one figure, so the choice can be seen.

``plot_curves(names=None, stops=(-10, 8), exposure=0.0)`` returns a matplotlib Figure (drawn with
the non-interactive Agg canvas: no display needed, nothing is written). The horizontal axis is the
scene-linear input on a log axis, labelled in stops from 1.0 (0 = an input of 1; middle grey 0.18
is -2.5); the left panel shows the sRGB-encoded display value a viewer sees, the right one the
display-linear output. reinhard2002 is drawn for an image whose log-average is middle grey. drago
and mantiuk are not per-pixel curves: they are drawn dashed as their response to a horizontal ramp
image covering the same range, which depends on the image.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Iterable

import numpy as np

from lenslab.errors import ToneError
from lenslab.srgb import encode as encode_srgb
from lenslab.tone.exposure import MIDDLE_GREY
from lenslab.tone.mapping import tonemap
from lenslab.tone.registry import CURVES, get_curve
from lenslab.tone.reinhard import reinhard2002

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_curves", "curve_samples"]


def curve_samples(name: str, stops=(-10.0, 8.0), exposure: float = 0.0, n: int = 512):
    """(input values, display-linear output), float32 arrays of ``n``, for plotting one curve."""
    x = np.exp2(np.linspace(stops[0], stops[1], n)).astype(np.float32)
    curve = get_curve(name)
    if curve.kind == "local":
        ramp = np.repeat(np.repeat(x[None, :, None], 8, axis=0), 3, axis=2)
        # a chart of every curve at one exposure: a curve the exposure does not change (mantiuk) takes none, and
        # the chart prints no note for it
        y = tonemap(ramp, curve.name, exposure=0.0 if curve.ignores_exposure else exposure)[4, :, 1]
    elif curve.kind == "image":
        y = reinhard2002(x * np.float32(2.0 ** exposure), log_avg=MIDDLE_GREY)
    else:
        y = tonemap(x, curve.name, exposure=exposure)
    return x, y


def plot_curves(names: Iterable[str] | str | None = None, stops: tuple[float, float] = (-10.0, 8.0),
                exposure: float = 0.0) -> "Figure":
    """Draw tone curves against scene-linear input, on one chart (what ``lenslab curves`` writes).

    Parameters
    ----------
    names : iterable of str, or str, optional
        Curves of :data:`lenslab.tone.CURVES` (a comma-separated string works too); default: all.
    stops : tuple of float
        The input range, from ``2**stops[0]`` to ``2**stops[1]``.
    exposure : float
        Stops applied before each curve.

    Returns
    -------
    matplotlib.figure.Figure
        Drawn on the non-interactive Agg canvas; save it with ``fig.savefig(path)``.

    Raises
    ------
    lenslab.errors.ToneError
        An unknown curve name, or an empty or reversed range.

    Examples
    --------
    >>> from lenslab.tone.plot import plot_curves
    >>> fig = plot_curves("reinhard,hable", stops=(-4, 4))
    >>> [line.get_label() for line in fig.axes[0].get_lines()][:2]
    ['reinhard', 'hable']
    """
    import matplotlib
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter

    if isinstance(names, str):
        names = names.split(",")
    chosen = [get_curve(n).name for n in (names or []) if str(n).strip()] or list(CURVES)
    lo, hi = (float(v) for v in stops)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ToneError(f"stops ({lo:g}, {hi:g}): give a finite range LOW < HIGH, such as (-10, 8)")
    exposure = float(exposure)

    fig = Figure(figsize=(14, 6), layout="constrained")
    ax_enc, ax_lin = fig.subplots(1, 2)
    cmap = matplotlib.colormaps["tab20"]
    for i, name in enumerate(chosen):
        x, y = curve_samples(name, (lo, hi), exposure)
        style = "--" if CURVES[name].kind == "local" else "-"
        for ax, values in ((ax_enc, encode_srgb(y)), (ax_lin, y)):
            ax.plot(x, values, style, color=cmap(i % 20), label=name, linewidth=1.6)
    for ax, title in ((ax_enc, "display value (sRGB-encoded)"), (ax_lin, "display-linear output")):
        ax.set_xscale("log", base=2)
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{np.log2(v):+.0f}"))
        ax.set_xlabel("scene-linear input, stops from 1.0")
        ax.set_title(title)
        ax.set_ylim(-0.02, 1.02)
        ax.axvline(MIDDLE_GREY, color="0.6", linewidth=0.8, linestyle=":")
        ax.grid(True, which="major", alpha=0.3)
    ax_enc.legend(loc="upper left", fontsize=9)
    fig.suptitle(f"lenslab tone curves (exposure {exposure:+g} stops; dotted line: middle grey 0.18)")
    return fig
