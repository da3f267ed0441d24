"""``lenslab tonemap --display``: the summary line names the display and view the OpenColorIO config
matched and used, not the words typed. The expected names come from PyOpenColorIO's own listing of the
built-in config (``getDisplays``, ``getDefaultView``), never from lenslab."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

ocio = pytest.importorskip("PyOpenColorIO")


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "grey.exr"
    lio.write(path, np.full((8, 8, 3), 0.18, np.float32))
    return path


def config_names(typed_display: str, typed_view: str | None):
    """(display, view) from OpenColorIO's own config: the display whose name before ' - ' is what was typed,
    and either the view holding the typed words or the display's default view."""
    config = ocio.Config.CreateFromFile("ocio://default")
    display = [d for d in config.getDisplays() if d.split(" - ")[0].lower() == typed_display.lower()]
    assert len(display) == 1
    if typed_view is None:
        return display[0], config.getDefaultView(display[0])
    views = [v for v in config.getViews(display[0]) if typed_view.lower() in v.lower()]
    assert len(views) == 1
    return display[0], views[0]


@pytest.mark.parametrize("typed_display, typed_view", [("sRGB", None), ("srgb", "un-tone"),
                                                      ("Display P3", None)])
def test_summary_names_what_was_used(scene, tmp_path, capsys, typed_display, typed_view):
    display, view = config_names(typed_display, typed_view)
    out = tmp_path / "out.png"
    argv = ["tonemap", str(scene), "-o", str(out), "--display", typed_display]
    if typed_view:
        argv += ["--view", typed_view]
    assert main(argv) == 0
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line == f"{out}: display {display}, view {view}"
    assert "(first)" not in line
