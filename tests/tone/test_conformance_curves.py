"""Every registered tone curve shows its published values, found from the curve registry.

Each curve module's docstring examples (run by ``--doctest-modules``) call the curve with an input and
the value its source publishes or its formula gives, transcribed by hand; this checks that every curve
the registry holds has such an example (a new curve without one fails here), and that the registry's
entry carries what the docs print.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

from lenslab.tone import CURVES


@pytest.mark.parametrize("name", list(CURVES))
def test_every_curve_has_an_example_with_its_value(name):
    curve = CURVES[name]
    module = importlib.import_module(curve.function.__module__)
    examples = [ex for test in doctest.DocTestFinder().find(module) for ex in test.examples]
    calls = [i for i, ex in enumerate(examples) if f"{curve.function.__name__}(" in ex.source]
    assert calls, f"{module.__name__}: no example calls {curve.function.__name__}()"
    # the call shows its value, or the next example does (a value computed from the call's result)
    assert any(ex.want.strip() for i in calls for ex in examples[i:i + 2])


@pytest.mark.parametrize("name", list(CURVES))
def test_every_curve_entry_says_what_it_is(name):
    entry = CURVES.entry(name)
    assert entry.summary and entry.capabilities["kind"] == entry.value.kind
    assert CURVES.canonical(name.upper().replace("-", "_")) == name
