"""``tracer bench --vs-mitsuba`` without Mitsuba (not a dependency of the project): it says so, records
no figure for it, and still writes its JSON record under the benchmark name "tracer"."""

from __future__ import annotations

import importlib.util
import json

from tracer.cli import main


def test_vs_mitsuba_without_mitsuba_says_so(tmp_path, monkeypatch, capsys):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "mitsuba" else real(name, *a))
    out = tmp_path / "tracer.json"
    assert main(["bench", "--mitsuba-only", "--json", str(out)]) == 0
    assert "mitsuba is not installed" in capsys.readouterr().out
    record = json.loads(out.read_text())
    assert record["benchmark"] == "tracer" and record["figures"] == []
