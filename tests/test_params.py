"""The one parameter type: conversion, description and the optimiser's search box, for lens models and
tone curves alike (the expected boxes are worked out by hand from the rule in the docstring)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab import params, tone
from lenslab.errors import LensError, ToneError
from lenslab.params import OPEN_END_MARGIN, SEARCH_FACTOR, Param


def test_lenses_and_curves_share_the_one_type():
    from lenslab.lenses import REGISTRY
    from lenslab.lenses.core.base import Param as LensParam

    assert LensParam is Param
    assert all(isinstance(p, Param) for cls in REGISTRY.values() for p in cls.params)
    assert all(isinstance(p, Param) for c in tone.CURVES.values() for p in c.params)


def test_the_existing_keyword_names_still_build_a_param():
    p = Param(name="k1", default=0.3, doc="r^2 coefficient", lo=0.0, hi=None, choices=None, lo_open=True,
              hi_open=False, units="")
    assert (p.kind, p.describe_range()) == (float, "(0, inf)")  # no bound above: inf itself is refused
    assert Param("white", math.inf, "", 0.0, math.inf, lo_open=True).describe_range() == "(0, inf]"
    assert Param("fov", 90.0, "fov", 0.0, 180.0, lo_open=True, hi_open=True, units="degrees").describe() == \
        "fov=90  (0, 180) degrees  fov"


@pytest.mark.parametrize("p, text, value", [
    (Param("fov", 90.0, "", 0.0, 180.0, lo_open=True), " 120 ", 120.0),
    (Param("n", 3, "", 1, 10), "4.0", 4),
    (Param("flip", False, ""), "yes", True),
    (Param("mapping", "equidistant", "", choices=("equidistant", "equisolid")), "EquiSolid", "equisolid"),
    (Param("white", math.inf, "", 0.0, math.inf, lo_open=True), "inf", math.inf),
])
def test_convert_gives_the_parameter_type(p, text, value):
    assert p.convert("model", text) == value


@pytest.mark.parametrize("p, text, words", [
    (Param("fov", 90.0, "", 0.0, 180.0, lo_open=True), "0", "out of range; give a number in (0, 180]"),
    (Param("fov", 90.0, "", 0.0, 180.0), "wide", "is not a number; give [0, 180]"),
    (Param("n", 3, "", 1, 10), "2.5", "is not a number"),
    (Param("k1", 0.0, ""), "inf", "must be a finite number"),  # no bound: infinity is not a value
    (Param("k1", 0.0, ""), "nan", "must be a finite number"),
    (Param("m", "a", "", choices=("a", "b")), "c", "choose one of a, b"),
])
def test_convert_refuses_with_what_is_valid(p, text, words):
    with pytest.raises(LensError, match="model: parameter") as info:
        p.convert("model", text)
    assert words in str(info.value)
    with pytest.raises(ToneError):  # the caller names the error type: a curve's parameter raises ToneError
        p.convert("curve 'x'", text, ToneError)


@pytest.mark.parametrize("p, start, box", [
    # positive: within a factor of 64 of the start, inside the range; an open end kept 1e-6 of the box away
    (Param("fov", 90.0, "", 0.0, 180.0, lo_open=True, hi_open=True), 90.0,
     (90 / 64, 180 - 1e-6 * (180 - 90 / 64))),
    (Param("fx", 500.0, "", 0.0, None, lo_open=True), 500.0, (500 / 64, 500 * 64)),
    (Param("A", None, "", 0.0, 10.0, lo_open=True), 0.15, (0.15 / 64, 0.15 * 64)),
    (Param("white", 11.2, "", 0.0, 1e6, lo_open=True), 11.2, (11.2 / 64, 11.2 * 64)),
    # not positive: the declared range, start +- max(1, |start|) on a side without a bound
    (Param("k1", 0.0, "", -1.0, 1.0), 0.0, (-1.0, 1.0)),
    (Param("k2", 0.0, ""), 0.3, (-0.7, 1.3)),
    (Param("k1", -0.3, "", None, 0.0, hi_open=True), -0.3, (-1.3, 0.0 - 1e-6 * 1.3)),
    (Param("pad", 0.0, "", 0.0, 64.0), 0.0, (0.0, 64.0)),
])
def test_search_bounds_by_the_rule(p, start, box):
    # a division, a multiplication and a margin in float64: a few ulps (1e-12 is a thousand of them)
    assert p.search_bounds(start) == pytest.approx(box, rel=1e-12, abs=1e-15)


@settings(max_examples=300, deadline=None)
@given(lo=st.one_of(st.none(), st.just(0.0), st.floats(-1e3, 1e3).filter(lambda v: abs(v) > 1e-6)),
       width=st.floats(1e-3, 1e4), hi_none=st.booleans(), lo_open=st.booleans(), hi_open=st.booleans(),
       frac=st.floats(0.001, 0.999))
def test_search_bounds_stay_inside_the_declared_range(lo, width, hi_none, lo_open, hi_open, frac):
    # the start is a valid value: strictly inside the range
    hi = None if hi_none else (0.0 if lo is None else lo) + width
    p = Param("x", 0.0, "", lo, hi, lo_open=lo_open, hi_open=hi_open)
    base = 0.0 if lo is None else lo
    start = base + frac * (width if hi is not None else 10.0)
    low, high = p.search_bounds(start)
    assert low < high
    assert lo is None or (low > lo if lo_open else low >= lo)
    assert hi is None or (high < hi if hi_open else high <= hi)
    assert low <= max(min(start, high), low) <= high  # the start can be clipped into it
    if lo is not None and lo >= 0 and start > 0:
        # within the factor, up to the rounding of one division or multiplication (1e-12 relative)
        assert low >= start / SEARCH_FACTOR * (1 - 1e-12) and high <= start * SEARCH_FACTOR * (1 + 1e-12)


def test_lens_and_tone_fits_take_their_boxes_from_the_param():
    from lenslab.fit.params import build_space
    from lenslab.fit.tone import _variables
    from lenslab.lenses import REGISTRY

    space = build_space("fisheye:mapping=equisolid", (400, 400), free="fov")
    fov = next(p for p in REGISTRY["fisheye"].params if p.name == "fov")
    assert (space.lower[0], space.upper[0]) == fov.search_bounds(fov.default)
    # Hable's A starts at its preset's value and gets the same rule as any other parameter
    (a,) = _variables("hable", ["A"], {}, {"preset": "gdc"})
    assert (a.start, a.lo, a.hi) == pytest.approx((0.22, 0.22 / 64, 10.0))  # 0.22 * 64 is past A's range (0, 10]
    assert OPEN_END_MARGIN < 1e-3 and params.format_value(math.inf) == "inf"
