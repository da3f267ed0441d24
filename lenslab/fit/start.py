"""Start values that follow a source lens: its principal point and its central scale.

A calibrated model fitted to another lens (``fit lens``, ``camera convert --model``) starts where the
source is: the same principal point (the pixel that sees the optical axis, in OpenCV's numbers) and
focal lengths that give it the source's pixels per radian next to the axis, measured on the target
model itself (a double sphere's central scale is ``fx / (1 + xi)``, a Kannala-Brandt camera's ``fx``).
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import FitError, LensError
from lenslab.lenses.core.base import Lens

CENTRAL_STEP = 0.25  # px either side of the principal point for the central scale


def principal_point(lens: Lens) -> tuple[float, float]:
    """The lenslab pixel that sees the optical axis (the image centre where the lens does not see it)."""
    xy, ok = lens.dir_to_pixel(np.array([[0.0, 0.0, 1.0]]))
    if ok[0]:
        return float(xy[0, 0]), float(xy[0, 1])
    return lens.width / 2.0, lens.height / 2.0


def central_scale(lens: Lens, at: tuple[float, float] | None = None) -> tuple[float, float]:
    """Pixels per radian along x and y at the principal point (central differences of the rays)."""
    x, y = principal_point(lens) if at is None else at
    h = CENTRAL_STEP
    pts = np.array([[x - h, y], [x + h, y], [x, y - h], [x, y + h]])
    d, ok = lens.pixel_to_dir(pts)
    if not ok.all():
        raise FitError(f"{lens.spec()}: no ray next to its principal point ({x:.2f}, {y:.2f}); cannot scale a "
                       "focal length from it")
    ax = 2.0 * np.arcsin(np.linalg.norm(d[1] - d[0]) / 2.0)
    ay = 2.0 * np.arcsin(np.linalg.norm(d[3] - d[2]) / 2.0)
    return 2.0 * h / ax, 2.0 * h / ay


def source_start(target_cls: type, source: Lens, given: dict) -> dict[str, float]:
    """Start values of a calibrated target's intrinsics that follow the source (those not ``given``):
    its principal point (OpenCV's numbers: lenslab's pixel minus 0.5) and focal lengths that give the
    target the source's central scale, with the target's other parameters at ``given`` or default."""
    names = getattr(target_cls, "intrinsic_names", ())
    if not {"fx", "fy", "cx", "cy"} <= set(names):
        return {}
    w, h = source.width, source.height
    px, py = principal_point(source)
    out = {"cx": px - 0.5, "cy": py - 0.5}
    sx, sy = central_scale(source, (px, py))
    probe = {p.name: p.default for p in target_cls.params if p.kind is float}
    probe.update({k: v for k, v in given.items() if k in probe})
    f0 = 0.25 * max(w, h)
    probe.update(fx=f0, fy=f0, cx=px - 0.5, cy=py - 0.5, width=w, height=h)
    try:
        tx, ty = central_scale(target_cls(w, h, **probe), (px, py))
    except (LensError, FitError):  # the target's own values leave no ray at the centre: keep its default
        tx = ty = None
    if tx is not None:
        out["fx"], out["fy"] = f0 * sx / tx, f0 * sy / ty
    gw, gh = int(given.get("width") or w), int(given.get("height") or h)
    if (gw, gh) != (w, h):  # the spec's calibration image is another size: its pixels
        out.update(target_cls.scale({**{k: probe[k] for k in ("fx", "fy", "cx", "cy")}, **out}, gw / w, gh / h))
    return {k: v for k, v in out.items() if k not in given}
