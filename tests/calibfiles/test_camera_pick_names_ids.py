"""``FILE#ID`` naming a camera the file does not hold: the one line lists the IDs the file does hold, said as
IDs (a single-camera OpenCV file's camera is ``0``; "it holds 0" read as "it holds no camera")."""

from __future__ import annotations

from lenslab.cli.main import main

COLMAP = """# Camera list with one line of data per camera:
#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]
3 SIMPLE_PINHOLE 640 480 500.0 320.0 240.0
7 PINHOLE 800 600 600.0 610.0 400.0 300.0
"""


def test_unknown_id_lists_the_file_ids(tmp_path, capsys):
    path = tmp_path / "cameras.txt"
    path.write_text(COLMAP)  # COLMAP's own cameras.txt layout, IDs 3 and 7
    assert main(["camera", "show", f"{path}#5"]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].endswith("no camera '5'; its camera IDs: 3, 7"), lines


def test_single_camera_file_says_its_id(tmp_path, capsys):
    import cv2
    import numpy as np

    path = tmp_path / "calib.yaml"
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)  # OpenCV's own writer
    fs.write("image_width", 640)
    fs.write("image_height", 480)
    fs.write("camera_matrix", np.array([[500.0, 0, 319.5], [0, 500.0, 239.5], [0, 0, 1]]))
    fs.write("distortion_coefficients", np.zeros((1, 5)))
    fs.release()
    assert main(["camera", "show", f"{path}#5"]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].endswith("no camera '5'; its camera ID: 0"), lines
