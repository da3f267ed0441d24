"""The reconstruction filters a warp reads its source with: one registry, from which the samplers
(:mod:`lenslab.warp.filters`), the command line's ``--filter`` choices, the docs' table and the
conformance tests derive.

Each :class:`Filter` says how far its kernel reaches (``radius``, in source pixels: a sample reads
``2 * radius`` taps per axis) and which compiled kernel computes it; the
registry entry carries its one-line summary, other names and the published source of its weights.
This module imports nothing heavy, so commands list the choices without loading the samplers.

>>> from lenslab.filters import FILTERS, filter_named
>>> list(FILTERS)
['nearest', 'bilinear', 'bicubic', 'lanczos']
>>> filter_named("Catmull-Rom"), FILTERS["lanczos"].radius
('bicubic', 3)
"""

from __future__ import annotations

from dataclasses import dataclass

from lenslab.errors import WarpError
from lenslab.registry import Registry


@dataclass(frozen=True)
class Filter:
    """One reconstruction filter: its canonical ``name``, its support ``radius`` in source pixels (the
    kernel is zero from there on) and ``code``, the id of its compiled kernel (:mod:`lenslab.warp.filters`)."""

    name: str
    radius: float
    code: int
    #: passes through the source's values at pixel centres
    interpolating: bool = True
    #: negative weights: may overshoot next to sharp edges (never clamped)
    overshoots: bool = False

    @property
    def taps(self) -> int:
        """Source pixels read per axis for one sample."""
        return round(2 * self.radius)


FILTERS: Registry[Filter] = Registry("filter", WarpError)


def _add(f: Filter, summary: str, references: tuple[str, ...], aliases: tuple[str, ...] = ()) -> None:
    caps = {"radius": f.radius, "taps": f.taps, "interpolating": f.interpolating, "overshoots": f.overshoots}
    FILTERS.add(f.name, f, aliases=aliases, summary=summary, capabilities=caps, references=references)


_add(Filter("nearest", 0.5, 0), "the pixel whose centre is nearest (ties go right and down)",
     ("box kernel: w(t) = 1 for -1/2 <= t < 1/2",))
_add(Filter("bilinear", 1, 1), "the 2 x 2 tent, w(t) = 1 - |t|", ("tent kernel: w(t) = max(0, 1 - |t|)",),
     aliases=("linear",))
_add(Filter("bicubic", 2, 2, overshoots=True),
     "Catmull-Rom, 4 x 4 taps: reproduces quadratics, overshoots a little at sharp edges",
     ("R. Keys, Cubic convolution interpolation for digital image processing, IEEE Trans. ASSP 29(6), 1981: "
      "the cubic with a = -1/2 (Catmull-Rom)",), aliases=("catmull-rom",))
_add(Filter("lanczos", 3, 3, overshoots=True),
     "Lanczos-3 windowed sinc, 6 x 6 taps, weights normalised to sum to 1",
     ("C. Lanczos, Applied Analysis, 1956; K. Turkowski, Filters for common resampling tasks, Graphics Gems I, "
      "1990: w(t) = sinc(t) sinc(t / 3) for |t| < 3",), aliases=("lanczos3",))


def filter_named(name: str) -> str:
    """The canonical name of filter ``name`` (or one of its other names); :class:`~lenslab.errors.WarpError`
    listing the filters for an unknown one."""
    if not isinstance(name, str) or name not in FILTERS:
        raise WarpError(f"unknown filter {name!r}; choose one of {', '.join(FILTERS)}")
    return FILTERS.canonical(name)


def check_filter_with_antialias(filter: str, antialias: bool, flags: tuple[str, str] = ("filter", "antialias")) -> None:
    """The footprint prefilter (``antialias``) averages the bilinear source over each pixel's footprint: it
    replaces the reconstruction filter, so another filter with it would be silently ignored.
    :class:`~lenslab.errors.WarpError` for that combination (``flags`` name the two options in it)."""
    if antialias and FILTERS.canonical(filter) != "bilinear":
        raise WarpError(f"{flags[0]} {FILTERS.canonical(filter)} does nothing with {flags[1]}: the footprint filter "
                        "replaces it (it averages the bilinear source over each pixel's footprint); give one")


def cli_filter(text: str) -> str:
    """``--filter``'s argument type: a filter's name or another name of it, as its canonical name; any
    other word is refused (argparse's one-line usage error), the message listing the filters."""
    import argparse

    if text not in FILTERS:
        raise argparse.ArgumentTypeError(f"unknown filter {text[:40]!r}; choose one of {', '.join(FILTERS)}")
    return FILTERS.canonical(text)


__all__ = ["Filter", "FILTERS", "filter_named", "cli_filter"]
