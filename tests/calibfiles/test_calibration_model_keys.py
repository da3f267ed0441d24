"""OpenCV calibration files: the keys that name a fisheye are read, an ambiguous file says which reading it
took and how to choose the other, and ``camera show`` names the model and every coefficient."""

from __future__ import annotations

import re
import subprocess
import sys

import cv2
import numpy as np
import pytest

# TUM-VI cam0 (512 x 512, Kannala-Brandt), as its calibration publishes it
K = np.array([[190.97847715128717, 0, 254.93170605935475], [0, 190.9733070521226, 256.8974428996504], [0, 0, 1]])
D = np.array([0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182])


def write_yaml(path, **keys):
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 512)
    fs.write("image_height", 512)
    for k, v in keys.items():
        fs.write(k, v)
    fs.write("camera_matrix", K)
    fs.write("distortion_coefficients", D.reshape(-1, 1))
    fs.release()
    return path


def show(path):
    return subprocess.run([sys.executable, "-m", "lenslab", "camera", "show", str(path)], capture_output=True,
                          text=True)


def fisheye_field_across_width():
    """cv2.fisheye's own answer: the angle between the rays of the left and right edge midpoints (OpenCV's
    pixel centres at integers: lenslab's x = 0 edge is OpenCV's -0.5)."""
    pts = np.array([[[-0.5, 255.5]], [[511.5, 255.5]]], np.float64)
    und = cv2.fisheye.undistortPoints(pts, K, D).reshape(-1, 2)
    rays = np.c_[und, np.ones(2)]
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    return np.degrees(np.arccos(np.clip(rays[:, 2], -1, 1)).sum())


def field(stdout):
    return float(re.search(r"field across the width ([\d.]+) deg", stdout).group(1))


@pytest.mark.parametrize("keys", [{"fisheye_model": 1}, {"distortion_model": "equidistant"},
                                  {"distortion_model": "fisheye"}, {"distortion_model": "kannala_brandt"},
                                  {"model": "equidistant"}, {"model": "fisheye"}, {"model": "kannala_brandt"}])
def test_fisheye_keys_are_read(tmp_path, keys):
    r = show(write_yaml(tmp_path / "cam.yaml", **keys))
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0].split(": ", 1)[1].startswith("kannala-brandt")
    for name, value in zip(("k1", "k2", "k3", "k4"), D):  # every coefficient by name
        assert re.search(rf"^\s+{name}\s+{float(value)!r}$", r.stdout, re.M)
    # 0.05 deg: cv2.fisheye.undistortPoints iterates to 1e-8 rad; the rest is printing to 0.01 deg
    assert abs(field(r.stdout) - fisheye_field_across_width()) < 0.05
    assert r.stderr == ""


def test_an_ambiguous_file_says_which_reading_and_how_to_choose(tmp_path):
    r = show(write_yaml(tmp_path / "cam.yaml"))
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0].split(": ", 1)[1].startswith("opencv")
    notes = [ln for ln in r.stderr.splitlines() if "note:" in ln]
    assert len(notes) == 1
    assert "read as OpenCV's pinhole model (k1 k2 p1 p2)" in notes[0]
    assert "distortion_model: equidistant" in notes[0]
    for name, value in zip(("k1", "k2", "p1", "p2"), D):
        assert re.search(rf"^\s+{name}\s+{float(value)!r}$", r.stdout, re.M)
    # the pinhole reading, checked against cv2.undistortPoints: its field differs from the fisheye's
    pts = np.array([[[-0.5, 255.5]], [[511.5, 255.5]]], np.float64)
    und = cv2.undistortPoints(pts, K, D).reshape(-1, 2)
    rays = np.c_[und, np.ones(2)]
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    assert abs(field(r.stdout) - np.degrees(np.arccos(rays[:, 2]).sum())) < 0.05
    # saying so silences the note
    r = show(write_yaml(tmp_path / "pin.yaml", distortion_model="plumb_bob"))
    assert r.returncode == 0 and "note:" not in r.stderr


def test_keys_that_disagree_or_unknown_words_fail_in_one_line(tmp_path):
    r = show(write_yaml(tmp_path / "a.yaml", fisheye_model=0, distortion_model="equidistant"))
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1 and "disagree" in r.stderr
    r = show(write_yaml(tmp_path / "b.yaml", distortion_model="mystery"))
    assert r.returncode == 1 and "unknown distortion_model" in r.stderr
