"""Mesh files checked before pyvista/VTK reads them (VTK crashes on hostile headers instead of failing):
a regular file of bounded size, and for PLY and binary STL, the element counts of the header against
the bytes the file holds (a PLY header declaring 4e9 vertices in a few hundred bytes is refused)."""

from __future__ import annotations

import os
from pathlib import Path

from tracer.scene import SceneError

#: the largest mesh file read
MAX_MESH_FILE = 2 << 30
_PLY_SIZES = {"char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2, "int16": 2, "uint16": 2,
              "int": 4, "uint": 4, "int32": 4, "uint32": 4, "float": 4, "float32": 4, "double": 8, "float64": 8}


def check_mesh_file(path: Path) -> None:
    from lenslab.inputs.sidefile import check_side_file

    check_side_file(path, "mesh file", MAX_MESH_FILE)
    size = os.path.getsize(path)
    suffix = path.suffix.lower()
    with open(path, "rb") as f:
        head = f.read(1 << 16)
    if suffix == ".ply":
        _check_ply(path, head, size)
    elif suffix == ".stl" and not head[:5].lower().startswith(b"solid") and len(head) >= 84:
        triangles = int.from_bytes(head[80:84], "little")
        if 84 + 50 * triangles > size:
            raise SceneError(f"{path}: the STL declares {triangles} triangles ({84 + 50 * triangles} bytes) but the "
                             f"file holds {size} bytes; it is truncated or damaged")


def _check_ply(path: Path, head: bytes, size: int) -> None:
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        raise SceneError(f"{path}: not a PLY file with a header of at most 64 KiB")
    ascii_ = b"format ascii" in head[:end]
    need, count, per = 0, 0, 0
    for line in head[:end].decode("latin-1").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "element" and len(words) == 3:
            need += count * per
            try:
                count = int(words[2])
            except ValueError:
                raise SceneError(f"{path}: the PLY element count {words[2][:20]!r} is not a number") from None
            if count < 0:
                raise SceneError(f"{path}: the PLY declares {count} {words[1][:20]} elements")
            per = 0
        elif words[0] == "property" and len(words) >= 3:
            if words[1] == "list":  # a count, then at least one value of a face (three for a triangle)
                per += 2 if ascii_ else _PLY_SIZES.get(words[2], 1) + _PLY_SIZES.get(words[3], 1)
            else:
                per += 2 if ascii_ else _PLY_SIZES.get(words[1], 1)
    need += count * per
    if need > size:
        raise SceneError(f"{path}: the PLY header declares elements needing at least {need} bytes but the file "
                         f"holds {size}; it is truncated, damaged or hostile")
