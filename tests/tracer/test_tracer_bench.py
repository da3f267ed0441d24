"""``tracer bench --vs-mitsuba`` without Mitsuba (not a dependency of the project): it says so, records
no figure for it, and still writes its JSON record under the benchmark name "tracer"."""

from __future__ import annotations

import importlib.util
import json
import math

from tracer.cli import main


def test_vs_mitsuba_without_mitsuba_says_so(tmp_path, monkeypatch, capsys):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "mitsuba" else real(name, *a))
    out = tmp_path / "tracer.json"
    assert main(["bench", "--mitsuba-only", "--json", str(out)]) == 0
    assert "mitsuba is not installed" in capsys.readouterr().out
    record = json.loads(out.read_text())
    assert record["benchmark"] == "tracer" and record["figures"] == []


def test_validate_records_the_warps_error_against_the_direct_trace(tmp_path, capsys):
    # --quick: a 1024x512 noise-free panorama of the Cornell box into a 128x128 fisheye, against the fisheye
    # traced directly at 16 spp (fixed sample positions: the figures are deterministic). Measured 0.651%
    # single-tap and 0.246% antialias; the antialiased warp must stay within the 0.3% the full-size aim
    # allows and well under the single tap (the footprint average is what the direct trace's pixel is)
    out = tmp_path / "tracer.json"
    assert main(["bench", "--validate-only", "--quick", "--repeat", "1", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "relative L1 against the direct trace" in printed
    figures = {f["key"]: f for f in json.loads(out.read_text())["figures"]}
    assert set(figures) == {"validate.single_tap_l1_quick", "validate.antialias_l1_quick",
                            "validate.antialias_cost_quick"}
    tap, aa = figures["validate.single_tap_l1_quick"]["value"], figures["validate.antialias_l1_quick"]["value"]
    assert aa < 0.3 and aa < 0.6 * tap, (aa, tap)
    # a ratio of two times: its size depends on the machine and its load, so only that it was measured
    # is checked here (`tracer bench` reports it; no test depends on timing)
    cost = figures["validate.antialias_cost_quick"]
    assert cost["unit"] == "x" and math.isfinite(cost["value"]) and cost["value"] > 0
    assert all(f["aim"] is None for f in figures.values())  # a smoke run has no aims
