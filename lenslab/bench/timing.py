"""Timing helpers shared by the benchmarks: best-of-N wall time, and ratios against a baseline."""

from __future__ import annotations

import time
from typing import Callable


def best_time(fn: Callable[[], object], repeat: int = 5, min_time: float = 0.0) -> float:
    """Best wall time in seconds of ``fn()`` over ``repeat`` runs (the least disturbed by other load)."""
    best = float("inf")
    start = time.perf_counter()
    n = 0
    while n < repeat or (time.perf_counter() - start) < min_time:
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
        n += 1
    return best


def ratio_line(label: str, seconds: float, baseline: float, extra: str = "") -> str:
    """One aligned report line: time, and the ratio to the baseline measured in the same run."""
    return f"{label:<40s} {seconds * 1e3:10.2f} ms   {seconds / baseline:7.2f}x baseline  {extra}".rstrip()
