"""An OpenCV pinhole camera with four distortion coefficients (k1 k2 p1 p2) is written with
``distortion_model: plumb_bob``: four numbers are also a fisheye's (k1..k4), so without the key lenslab's own
file read back gave the note that asks the user to add it. The file is checked with OpenCV's FileStorage."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lenslab.cli.main import main

cv2 = pytest.importorskip("cv2")

SPEC = "opencv:fx=900,fy=880,cx=639.5,cy=359.5,k1=-0.2,k2=0.05,p1=0.001,p2=-0.002,width=1280,height=720"


def test_the_file_says_pinhole_and_reads_back_without_a_note(tmp_path, capsys):
    out = tmp_path / "cal.yaml"
    assert main(["camera", "convert", SPEC, "-o", str(out)]) == 0
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    try:
        assert fs.getNode("distortion_model").string() == "plumb_bob"
        np.testing.assert_array_equal(fs.getNode("distortion_coefficients").mat().ravel(), [-0.2, 0.05, 0.001, -0.002])
        np.testing.assert_array_equal(fs.getNode("camera_matrix").mat(),
                                      [[900, 0, 639.5], [0, 880, 359.5], [0, 0, 1]])
    finally:
        fs.release()
    capsys.readouterr()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["camera", "show", str(out)]) == 0
    err = capsys.readouterr().err
    assert "distortion coefficients" not in err and "note" not in err, err


def test_five_coefficients_are_unambiguous_and_keep_the_file_as_it_was(tmp_path):
    out = tmp_path / "cal.yaml"
    assert main(["camera", "convert", SPEC.replace("p2=-0.002", "p2=-0.002,k3=0.01"), "-o", str(out)]) == 0
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    try:
        assert fs.getNode("distortion_model").empty()
        assert fs.getNode("distortion_coefficients").mat().size == 5
    finally:
        fs.release()
