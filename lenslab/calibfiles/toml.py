"""lenslab's own camera TOML (see :mod:`lenslab.lenses.core.cameraio`): every model, pose included."""

from __future__ import annotations

from pathlib import Path

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError


def sniff(path: Path, text: str) -> bool:
    return path.suffix.lower() == ".toml" or "[lens]" in text


def read(path: Path, text: str):
    from lenslab.lenses.core.cameraio import load_cameras

    try:
        return [(str(i), cam.lens) for i, cam in enumerate(load_cameras(path))]
    except LensError as exc:  # its message names the file
        raise CameraFileError(str(exc)) from None
    except (KeyError, TypeError) as exc:
        raise CameraFileError(f"{path}: missing or bad key {exc}") from None


def write(path: Path, lens) -> None:
    from lenslab.lenses import Camera

    Path(path).write_text(Camera(lens).to_toml(), encoding="utf-8")
