"""What a fit prints: its numbers with the digits the fit determines, as text a user can paste back.

A fitted value such as ``fov=189.99999999999997`` carries digits no fit determines. Every fit prints its numbers
with :data:`DIGITS` significant digits (``fov=190``, ``k1=-0.0203125``), and a lens fit with more only where the
camera needs them: :func:`fitted_text` rounds the fitted spec (and pose) to the fewest significant digits, 6 at
the least, for which the camera made from the printed text (read back through the spec grammar, as a user's paste
is) puts every pixel centre of a grid within ``budget`` pixels of where the fitted camera puts it. A value whose
only effect is within that budget (a roll of 1e-11 degrees, a ninth-order term of 1e-8) is not determined by the
fit at all: it is printed 0. The fits give a tenth of their own tolerance as that budget (:data:`SHARE`), so a
pasted value keeps the fit's verdict.
"""

from __future__ import annotations

import re
from typing import Sequence

import numpy as np

from lenslab.fit.problem import pixel_grid, project
from lenslab.lenses.core.base import Lens, format_number

#: significant digits of every printed fitted value, at the least
DIGITS = 6
#: the share of a fit's tolerance (px) the rounding of its printed values may use
SHARE = 0.1
#: samples along the longer side of the image where the printed camera is checked (edges included)
CHECK_GRID = 65

#: a spec value that is a decimal fraction or has an exponent (whole numbers, names and sizes are left alone)
_FRACTION = re.compile(r"(?<==)([-+]?(?:\d+\.\d*|\.\d+|\d+(?=[eE]))(?:[eE][-+]?\d+)?)(?=,|$)")


def significant(value: float, digits: int = DIGITS) -> str:
    """``value`` rounded to ``digits`` significant digits, written as the spec grammar and ``float`` read it:
    ``significant(189.99999999999997) == "190"``, ``significant(-0.020312512) == "-0.0203125"``."""
    return format_number(float(f"{float(value):.{digits}g}"))


def rounded_spec(spec: str, digits: int) -> str:
    """``spec`` (``model:key=value,...``) with every fractional value at ``digits`` significant digits."""
    return _FRACTION.sub(lambda m: significant(float(m.group(1)), digits), spec)


def fitted_text(lens: Lens, budget: float, ypr: Sequence[float] | None = None) -> tuple[str, tuple[str, ...]]:
    """The fitted ``lens``'s spec and its pose angles ``ypr`` (degrees, or None), as printed: the fewest
    significant digits (at least :data:`DIGITS`) for which the camera read back from the text places every
    pixel centre of a grid within ``budget`` px of the fitted one, with 0 for each value that matters less
    than that; the exact values (17 digits) when no rounding keeps within ``budget``."""
    exact = lens.spec()
    angles = [format_number(float(a)) for a in ypr] if ypr is not None else []
    try:
        moved = _Check(lens, budget, ypr)
    except NotImplementedError:  # a model without an inverse: nothing to measure a rounding by
        return exact, tuple(angles)
    if not len(moved.xy):  # no pixel the fitted camera maps and finds again
        return exact, tuple(angles)
    for digits in range(DIGITS, 17):
        text, turn = rounded_spec(exact, digits), [significant(a, digits) for a in angles]
        if moved(text, turn):
            break
    else:
        return exact, tuple(angles)
    spans = [m.span(1) for m in _FRACTION.finditer(text)]
    for a, b in reversed(spans):  # (from the end: the spans before stay where they are)
        if moved(text[:a] + "0" + text[b:], turn):
            text = text[:a] + "0" + text[b:]
    for i in range(len(turn)):
        if moved(text, turn[:i] + ["0"] + turn[i + 1:]):
            turn[i] = "0"
    return text, tuple(turn)


class _Check:
    """Whether the camera a printed spec and pose angles describe stays within ``budget`` px of the fitted one at
    the pixel centres of a grid (those the fitted camera maps and finds again)."""

    def __init__(self, lens: Lens, budget: float, ypr: Sequence[float] | None):
        from lenslab.lenses.core.pose import Pose

        self.size, self.budget, self.posed = (lens.width, lens.height), budget, ypr is not None
        xy = pixel_grid(self.size, CHECK_GRID)
        d, ok = lens.pixel_to_dir(xy)
        p, back = project(lens, d)
        keep = ok & back & (np.hypot(*(p - xy).T) <= budget)
        rotation = Pose.from_ypr(*ypr).rotation if ypr is not None else np.eye(3)
        self.xy, self.world = xy[keep], d[keep] @ rotation.T  # camera -> world (row vectors)

    def __call__(self, text: str, angles: Sequence[str]) -> bool:
        from lenslab.lenses import make_lens
        from lenslab.lenses.core.pose import Pose

        try:
            printed = make_lens(text, self.size)
            turn = Pose.from_ypr(*map(float, angles)).rotation if self.posed else np.eye(3)
        except Exception:  # noqa: BLE001 - a rounded value outside the model's range: not this text
            return False
        with np.errstate(all="ignore"):
            q, seen = project(printed, self.world @ turn)  # world -> the printed camera
            return bool(seen.all() and np.all(np.hypot(*(q - self.xy).T) <= self.budget))


__all__ = ["DIGITS", "SHARE", "significant", "rounded_spec", "fitted_text"]
