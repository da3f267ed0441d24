"""One record format for every benchmark: figures with their aim and whether the aim is met.

Every ``lenslab bench TARGET`` takes ``--json FILE``; a benchmark adds its figures with
:func:`figure` while it prints them, and the command writes them when it ends::

    from lenslab.bench.results import figure
    figure("warp.one_shot_bilinear", "one-shot bilinear vs cv2.remap", ratio, "x", aim=2.0, better="lower")

The JSON holds the benchmark's name, the machine's load average at the start and the end of the run, and
one row per figure: ``key`` (stable, dotted), ``label`` (what the speed table shows), ``value``,
``unit``, ``aim`` (or null), ``better`` (``lower``/``higher``), ``met`` (or null without an aim) and an
optional ``note``. ``tools/speed_table.py`` builds the speed table (docs/speed.md) from these files.
"""

from __future__ import annotations

import json
import os
import platform
import time
from typing import Any

_FIGURES: list[dict[str, Any]] = []


def met(value: float, aim: float | None, better: str = "lower") -> bool | None:
    """Whether ``value`` reaches ``aim`` (``better`` says which direction is good); None without an aim."""
    if aim is None:
        return None
    if better not in ("lower", "higher"):
        raise ValueError(f"better must be 'lower' or 'higher', got {better!r}")
    return bool(value <= aim) if better == "lower" else bool(value >= aim)


def figure(key: str, label: str, value: float, unit: str = "x", aim: float | None = None,
           better: str = "lower", note: str = "", detail: bool = False) -> bool | None:
    """Record one figure of the running benchmark; returns whether it meets its aim (None: no aim).

    ``detail=True`` keeps a figure in the JSON but out of the speed table (per-model rows that a
    summary row already covers)."""
    ok = met(float(value), aim, better)
    _FIGURES.append({"key": key, "label": label, "value": float(value), "unit": unit, "aim": aim,
                     "better": better, "met": ok, "note": note, "detail": bool(detail)})
    return ok


def mark(ok: bool | None) -> str:
    """The short word printed beside a figure: ``met``, ``MISSED`` or nothing."""
    return "" if ok is None else ("met" if ok else "MISSED")


def start() -> dict[str, Any]:
    """Forget earlier figures and note the run's start (load average, time)."""
    _FIGURES.clear()
    return {"started": time.time(), "load_start": _load()}


def write(path: str, benchmark: str, run: dict[str, Any], argv: list[str] | None = None,
          overwrite: bool = True) -> None:
    """Write the figures recorded since :func:`start` as JSON (temporary name, then rename)."""
    from lenslab.atomic import atomic_write_path

    record = {
        "benchmark": benchmark,
        "argv": argv or [],
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version()},
        "load_start": run.get("load_start"),
        "load_end": _load(),
        "seconds": round(time.time() - run.get("started", time.time()), 2),
        "figures": list(_FIGURES),
    }
    with atomic_write_path(path, overwrite=overwrite) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=1)
            f.write("\n")


def _load() -> list[float] | None:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - platforms without getloadavg
        return None
