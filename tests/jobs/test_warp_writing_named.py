"""A warp's bar does not sit at 100% in silence while a large output is written (an 8192 x 4096 float TIFF takes
longer to write than to warp): the write is named on the bar once it outlasts the patience."""

from __future__ import annotations

import io
import time

import numpy as np

from lenslab import io as lio
from lenslab.jobs import progress


def wait_for(text: str, stream: io.StringIO, seconds: float = 60.0) -> str:
    """What ``stream`` holds once it holds ``text`` (waiting for the state, not a duration), or at the deadline."""
    deadline = time.monotonic() + seconds
    while text not in stream.getvalue() and time.monotonic() < deadline:
        time.sleep(0.01)
    return stream.getvalue()


def test_a_step_named_after_the_last_band_shows_on_the_full_bar(monkeypatch):
    """Every band drawn (3 of 3), then the writing of ``big.tiff`` named: the bar, still on the terminal, says it."""
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    stream = io.StringIO()
    bar = progress.RowBar("pano.exr", stream)
    bar.start(3, unit="band")
    for _ in range(3):
        bar(8)
    bar.status("writing big.tiff")
    shown = wait_for("writing big.tiff", stream)
    bar.close()
    assert "3/3" in shown and "writing big.tiff" in shown, shown


def test_the_warp_names_its_output_before_writing_it(tmp_path, monkeypatch):
    """The step the command names between the last band and the write is the writing of the output given by -o."""
    steps = []
    monkeypatch.setattr(progress.RowBar, "status", lambda self, step: steps.append(step))
    monkeypatch.setattr(progress, "PATIENCE", 1e9)
    from lenslab.jobs.warp import WarpJob, plan_cache, warp_one

    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    job = WarpJob(to="equirect", size=(256, 128))
    bar = progress.RowBar("p.exr", io.StringIO())
    try:
        warp_one(str(tmp_path / "p.exr"), tmp_path / "wide.tiff", job, plan_cache(job), progress=bar)
    finally:
        bar.close()
    assert steps[-1] == "writing wide.tiff", steps
    assert lio.read(tmp_path / "wide.tiff")[0].shape == (128, 256, 4)
