"""A note on a camera file named by --to (an OpenCV file whose 4 coefficients could be a pinhole's or a fisheye's)
is printed once per command, not once more for each input of the batch. The file is written by OpenCV's own
FileStorage, as a calibration script would write it."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

cv2 = pytest.importorskip("cv2")


def _opencv_file(path) -> None:
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 64)
    fs.write("image_height", 48)
    fs.write("camera_matrix", np.array([[50.0, 0, 31.5], [0, 50.0, 23.5], [0, 0, 1]]))
    fs.write("distortion_coefficients", np.array([[-0.1], [0.01], [0.0], [0.0]]))
    fs.release()


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_the_camera_files_note_is_printed_once(tmp_path, capsys, jobs):
    cal = tmp_path / "cal.yaml"
    _opencv_file(cal)
    inputs = []
    for k in range(3):
        inputs.append(tmp_path / f"pano{k}.exr")
        write(inputs[-1], np.full((16, 32, 3), 0.25 * (k + 1), np.float32))
    assert main(["warp", *map(str, inputs), "-o", str(tmp_path / "out"), "--to", str(cal), "--jobs", jobs]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "4 distortion coefficients" in line]
    assert len(notes) == 1, notes
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["pano0.exr", "pano1.exr", "pano2.exr"]
