"""A photo stored on its side with an EXIF ``Orientation`` (a phone held upright) reads as shown, but a calibrated
camera (an OpenCV calibration, a camera file) describes the sensor's pixels as the camera stored
them: warping from it uses the stored frame, so the calibration is neither stretched to the turned size nor
mirrored. The oracle is OpenCV's ``IMREAD_UNCHANGED`` decode, which leaves the tag unapplied: a warp from the camera
to itself at its calibration size gives back the stored codes."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from PIL import Image

from lenslab.cli.main import main

CAMERA = "opencv:fx=60,fy=60,cx=31.5,cy=23.5,k1=-0.1,p1=0.002,width=64,height=48"


@pytest.mark.parametrize("orientation", [3, 6, 8])
def test_warp_from_the_calibrated_camera_uses_the_stored_frame(tmp_path, orientation):
    blocks = np.random.default_rng(3).integers(0, 256, (6, 8, 3))
    codes = np.kron(blocks, np.ones((8, 8, 1))).astype(np.uint8)  # 64 wide, 48 tall, as stored
    exif = Image.Exif()
    exif[0x0112] = orientation
    photo = tmp_path / "photo.jpg"
    Image.fromarray(codes).save(photo, quality=95, exif=exif.tobytes())
    stored = cv2.imread(str(photo), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(int)  # the tag not applied
    out = tmp_path / "same.png"
    assert main(["warp", str(photo), "--from", CAMERA, "--to", CAMERA, "--size", "64x48", "--filter", "bilinear", "-o", str(out)]) == 0
    got = cv2.imread(str(out), cv2.IMREAD_COLOR)[..., ::-1].astype(int)  # (its alpha: 1 at every centre)
    assert got.shape == stored.shape
    # every output pixel centre lands on a source pixel centre: the stored codes back, within the one code an
    # 8-bit sRGB encode of the decoded linear value may round to
    assert np.abs(got - stored).max() <= 1
