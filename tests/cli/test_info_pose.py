"""``lenslab info`` shows where a stored camera looks, beside its lens: a warp from the file starts from that pose,
so a perspective view turned 30 degrees must not read as one looking straight ahead."""

from __future__ import annotations

import math

import numpy as np

from lenslab import Camera, write
from lenslab.cli.main import main


def _pose_line(capsys, path) -> str:
    assert main(["info", str(path)]) == 0
    lines = [line.strip() for line in capsys.readouterr().out.splitlines() if line.strip().startswith("pose:")]
    assert len(lines) == 1, lines
    return lines[0]


def test_yaw_pitch_roll_and_eye_are_shown(tmp_path, capsys):
    path = tmp_path / "view.exr"
    cam = Camera.from_spec("perspective:fov=90", (8, 6), yaw=30, pitch=-10, roll=5, eye=(0, 1.5, 0))
    write(path, np.zeros((6, 8, 3), np.float32), camera=cam)
    assert _pose_line(capsys, path) == "pose: yaw 30, pitch -10, roll 5 degrees; eye (0, 1.5, 0)"


def test_a_look_at_pose_in_degrees(tmp_path, capsys):
    # from (0, 1.2, -3.2) towards (0, 0.4, 0): down by atan(0.8 / 3.2), straight ahead along +z
    path = tmp_path / "view.exr"
    cam = Camera.from_spec("fisheye:fov=180", (8, 8), eye=(0, 1.2, -3.2), look_at=(0, 0.4, 0))
    write(path, np.zeros((8, 8, 3), np.float32), camera=cam)
    pitch = -math.degrees(math.atan(0.8 / 3.2))
    assert _pose_line(capsys, path) == f"pose: yaw 0, pitch {pitch:.6g}, roll 0 degrees; eye (0, 1.2, -3.2)"


def test_no_pose_line_without_a_stored_camera(tmp_path, capsys):
    path = tmp_path / "plain.exr"
    write(path, np.zeros((4, 8, 3), np.float32))
    assert main(["info", str(path)]) == 0
    assert "pose:" not in capsys.readouterr().out
