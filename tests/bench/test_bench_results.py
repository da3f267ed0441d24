"""The benchmark record format and the README speed table built from it (tools/speed_table.py)."""

from __future__ import annotations

import json
import subprocess
import sys

from lenslab.bench import results
from tests.conftest import REPO


def test_met_follows_the_direction_of_the_aim():
    assert results.met(1.9, 2.0, "lower") is True
    assert results.met(2.1, 2.0, "lower") is False
    assert results.met(1.8, 1.7, "higher") is True
    assert results.met(1.6, 1.7, "higher") is False
    assert results.met(5.0, None) is None


def test_json_and_table_mark_missed_aims(tmp_path):
    run = results.start()
    results.figure("warp.cached", "cached map vs cv2.remap", 1.31, "x", aim=1.2)
    results.figure("cluster.speedup", "two workers vs one job", 1.8, "x", aim=1.7, better="higher")
    results.figure("io.pfm_read", "PFM read vs numpy.fromfile", 0.58, "x")
    results.figure("lenses.eac.p2d", "eac pixel -> dir", 2.7, "x", aim=3.0, detail=True)
    path = tmp_path / "warp.json"
    results.write(str(path), "warp", run, argv=["warp"])
    rec = json.loads(path.read_text())
    assert [f["met"] for f in rec["figures"]] == [False, True, None, True]
    readme = tmp_path / "README.md"
    readme.write_text("intro\n<!-- speed-table:start -->\nold\n<!-- speed-table:end -->\nafter\n")
    done = subprocess.run([sys.executable, str(REPO / "tools" / "speed_table.py"), str(path), "--readme", str(readme)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    body = readme.read_text()
    assert "old" not in body and body.startswith("intro\n") and body.endswith("after\n")
    assert "| `lenslab bench warp` | cached map vs cv2.remap | 1.31x | <= 1.2x | **missed** |" in body
    assert "| `lenslab bench warp` | two workers vs one job | 1.8x | >= 1.7x | met |" in body
    assert "| `lenslab bench warp` | PFM read vs numpy.fromfile | 0.58x | - | - |" in body
    assert "eac pixel -> dir" not in body  # detail rows stay in the JSON only
