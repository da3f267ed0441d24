"""Reading environment maps and writing renders, through lenslab's image I/O."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def read_image(path) -> np.ndarray:
    """An image file as float32 ``H x W x C`` linear light."""
    from lenslab.io import read

    image, _meta = read(path)
    return np.asarray(image, dtype=np.float32)


def write_image(path, image: np.ndarray, camera=None, overwrite: bool = True, attributes: dict | None = None) -> Path:
    """Write a float32 render; EXR keeps full float precision and carries the camera and ``attributes``; the
    other HDR formats (PFM, TIFF, Radiance HDR) hold the pixels only."""
    from lenslab.io import write
    from lenslab.io.registry import format_for_path, get

    path = Path(path)
    options = {}
    if path.suffix.lower() == ".exr":
        options["pixel_type"] = "float"
        if attributes:
            options["attributes"] = attributes
    if not get(format_for_path(path)).camera:
        camera = None  # a format without a place for the camera: the pixels alone, as --help says
    return write(path, np.ascontiguousarray(image, dtype=np.float32), overwrite=overwrite, camera=camera, **options)
