"""Cameras in TOML files: one camera, or several as ``[[cameras]]`` tables; tiled cameras included.

A camera file looks like::

    yaw = 30.0            # pose: yaw/pitch/roll in degrees, or at = [...] and up = [...], or rotation
    eye = [0.0, 1.5, 0.0]
    [lens]
    model = "fisheye"     # or: lens = "fisheye:fov=180,mapping=equisolid" with size = [W, H]
    size = [1024, 1024]
    fov = 180.0
    mapping = "equisolid"

A tiled camera's lens table holds its tiles as ``[[lens.tiles]]`` tables (lens, pose and eye each),
so per-tile eye points survive the trip; a hand-written ``lens = "tiled:2x2,tiles=cams.toml"`` reads
the tiles from ``cams.toml`` next to the camera file. Several cameras go in one file as ``[[cameras]]`` tables.
This is the same TOML that ``Camera.to_toml`` writes and image headers store.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from lenslab.errors import LensError
from lenslab.lenses.core.camera import Camera


def _read(path: str | Path) -> dict:
    from lenslab.inputs.safeload import load_toml
    from lenslab.inputs.sidefile import read_side_text

    path = Path(path)
    return load_toml(read_side_text(path, "camera file", 4 << 20), path, LensError)


def load_cameras(path: str | Path) -> list[Camera]:
    """Every camera in a TOML file: its ``[[cameras]]`` tables, or the one camera at the top level."""
    data = _read(path)
    tables = data.get("cameras", data.get("camera"))
    if tables is None:
        if "lens" not in data:
            raise LensError(f"{path}: no camera found; give a [lens] table (and a pose) or [[cameras]] tables")
        tables = [data]
    elif isinstance(tables, dict):
        tables = [tables]
    cams = []
    for i, table in enumerate(tables):
        try:
            cams.append(Camera.from_dict(_resolve_tiles_path(table, Path(path).parent)))
        except LensError as exc:
            raise LensError(f"{path}: camera {i}: {exc}") from None
    return cams


def _resolve_tiles_path(table: dict, folder: Path) -> dict:
    """A tiled lens's relative ``tiles=FILE`` is taken relative to the camera file's folder."""
    lens = table.get("lens") if isinstance(table, dict) else None
    if isinstance(lens, str) and lens.strip().lower().startswith("tiled"):
        name, _, rest = lens.partition(":")
        items = []
        for item in rest.split(",") if rest.strip() else []:
            key, eq, value = item.partition("=")
            if eq and key.strip() == "tiles" and value.strip() and not Path(value.strip()).is_absolute():
                item = f"tiles={folder / value.strip()}"
            items.append(item)
        return {**table, "lens": name + (":" + ",".join(items) if items else "")}
    if isinstance(lens, dict) and isinstance(lens.get("tiles"), str) and lens["tiles"].strip():
        tiles = Path(lens["tiles"].strip())
        if not tiles.is_absolute():
            return {**table, "lens": {**lens, "tiles": str(folder / tiles)}}
    return table


def load_camera(path: str | Path) -> Camera:
    """The one camera in a TOML file (an error if it holds several)."""
    cams = load_cameras(path)
    if len(cams) != 1:
        raise LensError(f"{path}: holds {len(cams)} cameras where one was expected; use load_cameras")
    return cams[0]


def save_camera(path: str | Path, camera: Camera, overwrite: bool = True) -> Path:
    """Write one camera as TOML (atomically: a temporary file renamed over the target)."""
    return _write(path, camera.to_toml(), overwrite)


def save_cameras(path: str | Path, cameras: Iterable[Camera], overwrite: bool = True) -> Path:
    """Write several cameras as ``[[cameras]]`` tables."""
    import tomli_w

    return _write(path, tomli_w.dumps({"cameras": [c.to_dict() for c in cameras]}), overwrite)


def _write(path: str | Path, text: str, overwrite: bool) -> Path:
    from lenslab.atomic import atomic_write_path

    with atomic_write_path(path, overwrite=overwrite) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return Path(path)
