"""``lenslab bench startup`` records each command's start-up and the first compile of a new machine: a
fresh process with an empty kernel cache warps into every lens; its figure is the time the first calls
took beyond the second ones, with the 3 s aim."""

from __future__ import annotations

import json
import math

from lenslab.cli.main import main


def test_startup_bench_records_the_commands_and_the_first_compile(tmp_path, capsys):
    out = tmp_path / "startup.json"
    assert main(["bench", "startup", "--commands", "convert", "--repeat", "1", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "first compile, every lens" in printed and "the lenses whose first warp compiled most" in printed
    figures = {f["key"]: f for f in json.loads(out.read_text())["figures"]}
    assert set(figures) == {"startup.convert", "startup.first_compile", "startup.first_compile_cpu"}
    assert figures["startup.first_compile"]["aim"] == 3.0 and figures["startup.convert"]["aim"] == 0.4
    # the figure is a duration (its size is the benchmark's to judge, never a test's: the kernels are
    # compiled when lenslab is installed, so a new machine's first warps compile next to nothing)
    for key in ("startup.first_compile", "startup.first_compile_cpu"):
        assert math.isfinite(figures[key]["value"]) and figures[key]["value"] >= 0.0
