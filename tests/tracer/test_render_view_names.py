"""``tracer render --view`` and ``--scene``: a name the scene or the ``--camera-file`` does not have, the
empty name included, is a usage error (exit 2, one line naming the ones there are), before anything is
rendered; the empty name never falls back to the first camera."""

from __future__ import annotations

import pytest

from tracer.cli import main

ARGS = ["render", "--size", "16x16", "--spp", "1", "-q"]

CAMERAS = """\
[near]
lens = { model = "fisheye", size = [16, 16], fov = 120.0 }
[far]
lens = { model = "perspective", size = [16, 16], fov = 40.0 }
"""


@pytest.mark.parametrize("view", ["", "no-such-view"])
def test_unknown_view_of_a_camera_file(tmp_path, capsys, view):
    cams = tmp_path / "cams.toml"
    cams.write_text(CAMERAS)
    out = tmp_path / "r.exr"
    assert main([*ARGS, "--camera-file", str(cams), "--view", view, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].endswith("it has near, far"), err
    assert not out.exists()


def test_a_named_camera_of_the_file_renders(tmp_path):
    cams = tmp_path / "cams.toml"
    cams.write_text(CAMERAS)
    assert main([*ARGS, "--scene", "furnace", "--camera-file", str(cams), "--view", "far",
                 "-o", str(tmp_path / "r.exr")]) == 0


@pytest.mark.parametrize("view", ["", "no-such-view"])
def test_unknown_view_of_a_built_in_scene(tmp_path, capsys, view):
    out = tmp_path / "r.exr"
    assert main([*ARGS, "--scene", "cornell", "--view", view, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--view {view!r}: scene cornell has no view" in err[0], err
    assert not out.exists()


def test_a_scene_name_that_is_neither_built_in_nor_a_scene_file_is_a_usage_error(tmp_path, capsys):
    out = tmp_path / "r.exr"
    assert main([*ARGS, "--scene", "cornel", "-o", str(out)]) == 2  # a typo, known from the name alone
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'cornel' is neither a built-in scene" in err[0], err
    assert main([*ARGS, "--scene", str(tmp_path / "missing.obj"), "-o", str(out)]) == 1  # a file that is not there
    assert not out.exists()
