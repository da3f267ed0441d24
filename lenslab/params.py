"""One parameter type for everything a user sets by name: lens models and tone curves alike.

A :class:`Param` declares a name, a default, a range (``lo``/``hi``, either end open or closed,
``None`` for no bound; ``math.inf`` as a closed end also accepts infinity itself), or a set of
``choices``, the units and a line of documentation. The same record serves the three places that
need it: :meth:`Param.convert` turns a user's value (often text from a spec or the command line)
into the parameter's type and checks it, :meth:`Param.describe` says what is valid (``lenslab
lenses``, ``lenslab curves --list`` and every error message), and :meth:`Param.search_bounds` gives
the box an optimiser moves the parameter in (``lenslab fit``, for lenses and curves alike).

>>> p = Param("fov", 90.0, "horizontal field of view", 0.0, 180.0, lo_open=True, hi_open=True, units="degrees")
>>> p.describe_range()
'(0, 180)'
>>> p.convert("perspective", "120")
120.0
>>> p.search_bounds(90.0)
(1.40625, 179.99982140625)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from lenslab.errors import LensError

#: a positive parameter searches within a factor of this of its start (both ways), inside its range
SEARCH_FACTOR = 64.0
#: fraction of the search range kept away from an open end of the declared range (a fov below 180)
OPEN_END_MARGIN = 1e-6


def format_value(v: Any) -> str:
    """Short text for a value: ``90``, ``0.15``, ``inf``, ``blog``."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return str(v)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return f"{v:g}"


@dataclass(frozen=True)
class Param:
    """One named parameter: a number in a range, a boolean, an integer, or one of ``choices``.

    ``default=None`` means the value is derived from other parameters (``doc`` says how); such a
    parameter is a real number when given.
    """

    name: str
    default: Any
    doc: str
    lo: float | None = None  # None: unbounded below
    hi: float | None = None
    choices: tuple[str, ...] | None = None
    lo_open: bool = False  # True: the bound itself is excluded
    hi_open: bool = False
    units: str = ""

    @property
    def kind(self) -> type:
        """The type a value is converted to: ``str``, ``bool``, ``int`` or ``float``."""
        if self.choices is not None or isinstance(self.default, str):
            return str
        if isinstance(self.default, bool):
            return bool
        if isinstance(self.default, int):
            return int
        return float

    # -- describing ----------------------------------------------------------------------------
    def describe_range(self) -> str:
        """``(0, 180)``, ``[0, inf)`` (no bound: an open end), ``(0, inf]`` (infinity itself allowed),
        ``any``, ``true or false`` or ``one of blog, gdc``."""
        if self.choices is not None:
            return "one of " + ", ".join(self.choices)
        if self.kind is bool:
            return "true or false"
        if self.lo is None and self.hi is None:
            return "any"
        lo = "(-inf" if self.lo is None else ("(" if self.lo_open else "[") + format_value(self.lo)
        hi = "inf)" if self.hi is None else format_value(self.hi) + (")" if self.hi_open else "]")
        return f"{lo}, {hi}"

    def describe(self) -> str:
        """One line: ``name=default  range  units  doc``."""
        default = "(derived)" if self.default is None else format_value(self.default)
        units = f" {self.units}" if self.units else ""
        return f"{self.name}={default}  {self.describe_range()}{units}  {self.doc}"

    # -- converting ----------------------------------------------------------------------------
    def convert(self, owner: str, value: Any, error: type[Exception] = LensError) -> Any:
        """``value`` (a number, or text as a spec or the command line gives it) as this parameter's
        type, checked against its range or choices; ``error`` (a lenslab error type) says what is wrong
        and what is valid, prefixed by ``owner`` (the model or curve)."""
        kind = self.kind
        what = f"{owner}: parameter {self.name}"
        try:
            if kind is bool:
                value = _to_bool(value)
            elif kind is int:
                number = float(value)
                if number != int(number):
                    raise ValueError(value)
                value = int(number)
            elif kind is float:
                value = float(value)
            else:
                value = str(value)
        except (TypeError, ValueError, OverflowError):
            expected = "a number" if kind in (int, float) else f"a {kind.__name__}"
            raise error(f"{what}={value!r} is not {expected}; give {self.describe_range()}") from None
        if kind is str:
            return self._choice(what, value, error)
        if kind in (int, float):
            self._check_range(what, value, error)
        return value

    def _choice(self, what: str, value: str, error: type[Exception]) -> str:
        if self.choices is None or value in self.choices:
            return value
        key = value.strip().lower()
        for c in self.choices:
            if c.lower() == key:
                return c
        raise error(f"{what}={value!r} is not valid; choose one of {', '.join(self.choices)}")

    def _check_range(self, what: str, value: float, error: type[Exception]) -> None:
        infinite_ok = (value == math.inf and self.hi == math.inf and not self.hi_open) or \
                      (value == -math.inf and self.lo == -math.inf and not self.lo_open)
        if math.isnan(value) or (math.isinf(value) and not infinite_ok):
            span = self.describe_range()
            raise error(f"{what} must be a finite number, got {format_value(value)}; "
                        f"give {'a finite number' if span == 'any' else 'a number in ' + span}")
        low = self.lo is not None and (value < self.lo or (self.lo_open and value == self.lo))
        high = self.hi is not None and (value > self.hi or (self.hi_open and value == self.hi))
        if low or high:
            default = "" if self.default is None else f" (default {format_value(self.default)})"
            raise error(f"{what}={format_value(value)} is out of range; give a number in "
                        f"{self.describe_range()}{default}")

    # -- optimiser bounds ------------------------------------------------------------------------
    def search_bounds(self, start: float) -> tuple[float, float]:
        """The box ``(low, high)`` an optimiser moves this parameter in, starting from ``start``.

        Inside the declared range always. A positive parameter (range starting at 0 or above, start
        above 0) moves within a factor of :data:`SEARCH_FACTOR` of its start, so that a white point
        of 4 or a focal length of 500 px is searched on its own scale; any other parameter moves
        over its declared range, or ``start +- max(1, |start|)`` on a side without a bound. An open
        end of the declared range is kept a small margin away (:data:`OPEN_END_MARGIN`)."""
        if self.kind is not float:
            raise TypeError(f"parameter {self.name} is not a real number: it has no search bounds")
        start = float(start)
        lo = self.lo if self.lo is not None and math.isfinite(self.lo) else None
        hi = self.hi if self.hi is not None and math.isfinite(self.hi) else None
        if lo is not None and lo >= 0 and start > 0:
            low, high = max(lo, start / SEARCH_FACTOR), start * SEARCH_FACTOR
            high = high if hi is None else min(hi, high)
        else:
            half = max(1.0, abs(start))
            low = lo if lo is not None else (start if hi is None else min(start, hi)) - half
            high = hi if hi is not None else (start if lo is None else max(start, lo)) + half
        margin = OPEN_END_MARGIN * (high - low)
        if self.lo_open and lo is not None and low <= lo:
            low = lo + margin
        if self.hi_open and hi is not None and high >= hi:
            high = hi - margin
        return low, high


def _to_bool(value: Any) -> bool:
    if isinstance(value, str):
        text = value.strip().lower()
        if text not in ("true", "false", "1", "0", "yes", "no"):
            raise ValueError(value)
        return text in ("true", "1", "yes")
    return bool(value)
