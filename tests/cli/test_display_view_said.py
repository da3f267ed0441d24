"""Every command that writes through an OpenColorIO display says, once, which display and view it used, in
the same words (``OUTPUT: display D, view V``). Expected names: PyOpenColorIO's own answer for the config
(``getDisplays``, ``getDefaultView``), not lenslab's resolution of them."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

ocio = pytest.importorskip("PyOpenColorIO")


def _expected(part: str, view: str | None = None) -> str:
    config = ocio.Config.CreateFromFile("ocio://default")
    (display,) = [d for d in config.getDisplays() if part in d and "HDR" not in d]
    return f"display {display}, view {view or config.getDefaultView(display)}"


@pytest.fixture
def exr(tmp_path):
    path = tmp_path / "scene.exr"
    lio.write(path, np.random.default_rng(3).uniform(0, 2, (8, 16, 3)).astype(np.float32))
    return path


def _said(capsys, out) -> list[str]:
    return [line for line in capsys.readouterr().err.splitlines() if line.startswith(f"{out}: display ")]


@pytest.mark.parametrize("command", [
    ["convert"],
    ["tonemap"],
    ["warp", "--to", "fisheye:fov=180", "--size", "8x8"],
])
def test_the_default_view_is_said_once(tmp_path, capsys, exr, command):
    out = tmp_path / "out.png"
    assert main([command[0], str(exr), *command[1:], "--display", "Display P3", "-o", str(out)]) == 0
    assert _said(capsys, out) == [f"{out}: {_expected('Display P3')}"]


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["tonemap"]])
def test_many_files_say_it_once_for_the_folder(tmp_path, capsys, exr, command):
    other = tmp_path / "second.exr"
    other.write_bytes(exr.read_bytes())
    out = tmp_path / "shown"
    assert main([command[0], str(exr), str(other), *command[1:], "--display", "sRGB", "-o", str(out)]) == 0
    assert _said(capsys, out) == [f"{out}: {_expected('sRGB')}"]


def test_a_view_asked_is_the_view_said(tmp_path, capsys, exr):
    config = ocio.Config.CreateFromFile("ocio://default")
    display = next(d for d in config.getDisplays() if d.startswith("sRGB"))
    view = list(config.getViews(display))[-1]  # not the default one
    assert view != config.getDefaultView(display)
    out = tmp_path / "out.png"
    assert main(["convert", str(exr), "--display", "sRGB", "--view", view, "-o", str(out)]) == 0
    assert _said(capsys, out) == [f"{out}: display {display}, view {view}"]


def test_quiet_says_nothing(tmp_path, capsys, exr):
    out = tmp_path / "out.png"
    assert main(["convert", str(exr), "--display", "sRGB", "-q", "-o", str(out)]) == 0
    assert _said(capsys, out) == []
