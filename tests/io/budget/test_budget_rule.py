"""The input budget's rule (lenslab.io.budget.allowed), against its formula transcribed here in integers:
a file of b bytes may decode to max(96 MiB, R * min(b, 1 MiB) + 4096 * max(b - 1 MiB, 0)) bytes of float32,
R = 512 (measured: see lenslab/io/budget.py). Continuous and increasing in b: no size where one more
byte admits gigabytes more, as a file of 1 MiB did against one of 1 MiB less a byte."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.io import budget
from lenslab.io.budget import BudgetError, Declared, allowed, check

BASE, KNEE, R, BEYOND = 96 << 20, 1 << 20, 512, 4096

sizes = st.integers(min_value=0, max_value=64 << 20)


def _formula(b: int) -> int:
    return max(BASE, R * min(b, KNEE) + BEYOND * max(b - KNEE, 0))


def test_the_constants_are_the_measured_ones():
    assert (budget.BASE_BYTES, budget.SMALL_FILE, budget.SMALL_RATIO, budget.MAX_RATIO) == (BASE, KNEE, R, BEYOND)


@given(sizes)
def test_allowed_is_the_formula(b):
    assert allowed(b) == _formula(b)


@given(sizes, st.integers(min_value=1, max_value=1 << 20))
@settings(max_examples=300)
def test_allowed_is_continuous_and_increasing(b, step):
    """One more byte buys at most 4096 bytes of float (the steeper of the two ratios), never less than
    none: |allowed(b + d) - allowed(b)| <= 4096 d."""
    assert 0 <= allowed(b + step) - allowed(b) <= BEYOND * step


@pytest.mark.parametrize("b, expected", [
    (300, BASE),                        # a 300-byte file: the base, 96 MiB
    (BASE // R, BASE),                  # 192 KiB: where R * b reaches the base
    (850_000, 435_200_000),             # a 0.85 MB 12 MP JPEG: 512 * 850 000 bytes, over its 146 MB
    (KNEE - 1, R * (KNEE - 1)),
    (KNEE, R * KNEE),                   # 512 MiB
    (KNEE + 1, R * KNEE + BEYOND),
    (2 * KNEE, (R + BEYOND) * KNEE),    # 4.5 GiB
])
def test_pinned_values(b, expected):
    assert allowed(b) == expected


@given(st.integers(min_value=0, max_value=KNEE + (KNEE // 3)))  # (up to 1.9 GiB: within LENSLAB_MAX_PIXELS)
@settings(max_examples=60)
def test_a_declared_image_at_the_edge_is_admitted_and_one_row_more_refused(b):
    """A header declaring the most rows of 4096 grey pixels within the formula's bytes passes :func:`check`;
    one row more is refused in one line naming the LENSLAB_BASE_BYTES value that admits it."""
    rows = _formula(b) // (4 * 4096)
    check("f", Declared(4096, rows, channels=1), b)
    with pytest.raises(BudgetError) as caught:
        check("f", Declared(4096, rows + 1, channels=1), b)
    message = str(caught.value)
    assert "\n" not in message and f"LENSLAB_BASE_BYTES={4 * 4096 * (rows + 1)}" in message


def test_lenslab_small_ratio_sets_r():
    """LENSLAB_SMALL_RATIO=1: every file under 1 MiB decodes to at most 96 MiB again (each byte of the first
    MiB buys 1 byte), and the rule stays continuous at 1 MiB: 1 MiB + 4096 per byte beyond."""
    import os
    import subprocess
    import sys

    code = "from lenslab.io.budget import allowed; print(allowed(850_000), allowed(1 << 20), allowed((1 << 20) + 10))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, LENSLAB_SMALL_RATIO="1"))
    assert done.returncode == 0, done.stderr
    assert [int(v) for v in done.stdout.split()] == [BASE, BASE, max(BASE, KNEE + 10 * BEYOND)]
