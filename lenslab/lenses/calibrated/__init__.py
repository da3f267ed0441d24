"""Camera models calibrated elsewhere (OpenCV, cv2.fisheye, cv2.omnidir, Kalibr, COLMAP, Basalt,
OCamCalib), their numbers taken verbatim. What they share (OpenCV's pixel and camera frames,
intrinsics, scaling) is :mod:`lenslab.lenses.calibrated.intrinsics`, re-exported here; a new model is
one module in this package that subclasses :class:`Calibrated` and registers itself."""

from lenslab.lenses.calibrated.intrinsics import (  # noqa: F401
    DEFAULT_CALIBRATION, SIZE_PARAMS, Calibrated, coefficient_params, intrinsics_params, unit_rows)
