"""A single ``lenslab convert`` or ``lenslab tonemap`` on a terminal names each step that outlasts the patience
(convert: reading, converting, then writing NAME; tonemap: reading, then tone-mapping and writing NAME: encoding an
8000 x 8000 PNG takes seconds), instead of a "reading..." that stays the last word (convert) or nothing at all until
the summary (tonemap, 43 s for such a file on a loaded machine). Read from what a pseudo-terminal received."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.jobs import progress
from tests.warp.test_progress_writing import _held_until_said
from tests.warp.test_warp_progress import on_terminal


@pytest.mark.parametrize("command, step, said, summary", [
    ("convert", "writing", "p.exr: writing o.png...", "converted 1 of 1 file(s) to PNG"),
    ("tonemap", "tone-mapping", "p.exr: tone-mapping and writing o.png...", "o.png: 32 x 16, curve"),
])
def test_a_slow_write_is_named(tmp_path, monkeypatch, command, step, said, summary):
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.full((16, 32, 3), 0.5, np.float32))
    _held_until_said(monkeypatch, lio, "write", step=step, output="o.png")
    code, out = on_terminal(monkeypatch, [command, str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.png")])
    assert code == 0
    assert said in out, out
    assert out.index(said) < out.index(summary)
