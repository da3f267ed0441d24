"""OCamCalib's ``calib_results.txt`` (Scaramuzza's toolbox, as its ``get_ocam_model`` reads it).

Five data lines between ``#`` comments: ``N a0 a1 ... `` (the cam2world polynomial), ``M p0 p1 ...``
(world2cam's inverse polynomial), ``xc yc`` (centre row and column, counted from 0: the C convention,
pixel centres at integers), ``c d e`` (affine) and ``height width``.
"""

from __future__ import annotations

import math
from pathlib import Path

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError, clip
from lenslab.lenses.core.base import MAX_SIDE

LABELS = ("the polynomial line", "the inverse polynomial line", "the centre line (xc yc)",
          "the affine line (c d e)", "the size line (height width)")


def sniff(path: Path, text: str) -> bool:
    return "cam2world" in text or "DIRECT mapping function" in text or path.name.startswith("calib_results")


def _data_lines(path: Path, text: str) -> list[list[float]]:
    rows = []
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        try:
            row = [float(p) for p in s.split()]
        except ValueError:
            row = []
        if not row or not all(math.isfinite(v) for v in row) or len(row) > 64:
            raise CameraFileError(f"{path}: {LABELS[min(len(rows), 4)]} must hold at most 64 finite numbers, got "
                                  f"{clip(s)}")
        rows.append(row)
        if len(rows) == 5:
            break
    return rows


def read(path: Path, text: str):
    from lenslab.lenses import make_lens
    from lenslab.lenses.calibrated.ocam import format_coefficients

    rows = _data_lines(path, text)
    if len(rows) < 5:
        raise CameraFileError(f"{path}: missing {LABELS[len(rows)]}")
    pol, inv, centre, affine, size = rows[:5]
    for label, row in ((LABELS[0], pol), (LABELS[1], inv)):
        if not row or row[0] != len(row) - 1:
            raise CameraFileError(f"{path}: {label} must start with its count of coefficients")
    for label, row, n in ((LABELS[2], centre, 2), (LABELS[3], affine, 3), (LABELS[4], size, 2)):
        if len(row) != n:
            raise CameraFileError(f"{path}: {label} needs {n} numbers, got {len(row)}")
    if not all(v == int(v) and 1 <= v <= MAX_SIDE for v in size):
        raise CameraFileError(f"{path}: {LABELS[4]} must hold two whole numbers of pixels in 1..{MAX_SIDE}")
    h, w = int(size[0]), int(size[1])
    values = {"pol": format_coefficients(pol[1:]), "invpol": format_coefficients(inv[1:]),
              "xc": centre[0], "yc": centre[1], "c": affine[0], "d": affine[1], "e": affine[2],
              "width": w, "height": h}
    try:
        return [("0", make_lens({"model": "ocam", **values}, (w, h)))]
    except LensError as exc:  # a bad value in the file
        raise CameraFileError(f"{path}: {exc}") from None


def write(path: Path, lens) -> None:
    if lens.name != "ocam":
        raise LensError(f"OCamCalib files hold the ocam model only, not {lens.name}")
    pol, inv = lens.pol_c, lens.invpol_c

    def line(c):
        return f"{len(c)} " + " ".join(repr(float(x)) for x in c)

    text = ("#polynomial coefficients for the DIRECT mapping function (ocam_model.ss in MATLAB). "
            "These are used by cam2world\n\n" + line(pol) + "\n\n"
            "#polynomial coefficients for the inverse mapping function (ocam_model.invpol in MATLAB). "
            "These are used by world2cam\n\n" + line(inv) + "\n\n"
            '#center: "row" and "column", starting from 0 (C convention)\n\n'
            f"{lens.xc!r} {lens.yc!r}\n\n"
            '#affine parameters "c", "d", "e"\n\n'
            f"{lens.c!r} {lens.d!r} {lens.e!r}\n\n"
            '#image size: "height" and "width"\n\n'
            f"{lens.height} {lens.width}\n")
    Path(path).write_text(text, encoding="utf-8")
