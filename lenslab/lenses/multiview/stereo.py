"""Stereo frames: two eyes of one projection, side by side or top and bottom (VR180, 3D 360 video)."""

from __future__ import annotations

from typing import Any

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import Lens, Param, Piece, ReferencePoint, as_points, clean
from lenslab.lenses.core.pose import Pose
from lenslab.lenses.registry import lens_class, register

LAYOUTS = ("sbs", "tb")


@register
class Stereo(Lens):
    r"""Stereo frame: two eyes of one base projection, side by side (sbs) or top and bottom (tb).

    ``sbs`` puts the left eye in the left half and the right eye in the right half, ``tb`` the left eye
    on top, as VR180 and 3D 360 video store them.

    Each half is the base lens at the half's size (``W/2 x H`` or ``W x H/2``; the split side must be
    even): ``stereo:sbs,base=half-equirect`` is a VR180 frame, ``stereo:tb,base=equirect`` a
    top-bottom 3D 360 frame; the base's own parameters pass through (``stereo:sbs,base=fisheye,fov=190``).

    The warp engine reads the eyes from :meth:`pieces` (each piece carries its eye number and the base
    lens at the half's size): a stereo output takes each eye from the same eye of a stereo source (or
    both eyes from one mono source), and a mono output takes the left eye of a stereo source, as ffmpeg's
    v360 does with ``in_stereo``/``out_stereo``. The lens's own maps, used outside a warp, treat the
    frame as two copies of the base: a pixel sees its half's direction, and a direction is found in the
    left (top) eye.
    """

    name = "stereo"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ("stereo:sbs,base=fisheye,fov=190", (8192, 4096)),
        ("stereo:tb,base=equirect", (8192, 8192)),
    )
    #: the base models' pinned points (fisheye: Kannala and Brandt's equisolid formula; equirect: the
    #: latitude/longitude definition) in the left eye: the left half (sbs) or top half (tb) at the base's
    #: size. A direction maps to the left eye, so the right eye's copy holds one way only (its own test).
    reference_points = (
        ReferencePoint("stereo:sbs,base=fisheye,fov=180,mapping=equisolid", (1024, 512), (400.25, 130.5),
                       (0.6766798510869233, 0.5887231979993682, 0.4421644210815432),
                       "equisolid r = 2 f sin(theta/2) (Kannala and Brandt 2006, table 1), float64, left eye"),
        ReferencePoint("stereo:tb,base=equirect", (800, 800), (620.25, 130.5),
                       (0.8438986849711829, 0.5191462344390729, -0.13535950935061536),
                       "latitude/longitude definition (v360 equirect), float64, top (left) eye"),
    )
    summary = "two eyes of one projection, side by side (sbs) or top and bottom (tb): VR180, 3D 360"
    positional = "layout"
    params = (
        Param("layout", "sbs", "where the right eye is: sbs = right half, tb = bottom half", choices=LAYOUTS),
        Param("base", "equirect", "the projection of each eye (its parameters pass through)"),
    )

    def __init__(self, width: int, height: int, **values: Any):
        own = {k: v for k, v in values.items() if k in ("layout", "base")}
        rest = {k: v for k, v in values.items() if k not in own}
        base_name = str(own.get("base", "equirect")).strip().lower()
        if base_name == self.name:
            raise LensError("stereo: base=stereo makes no sense; give the projection of one eye")
        base_cls = lens_class(base_name)
        known = {p.name for p in base_cls.params}
        unknown = sorted(set(rest) - known)
        if unknown:
            raise LensError(f"stereo: unknown parameter(s) {', '.join(unknown)}; valid: layout, base, "
                            + (", ".join(f"{n} (of base {base_name})" for n in sorted(known)) or "none of the base"))
        own["base"] = base_name
        super().__init__(width, height, **own)
        sbs = self.layout == "sbs"
        split = self.width if sbs else self.height
        if split % 2:
            raise LensError(f"stereo:{self.layout}: the {'width' if sbs else 'height'} must be even to hold two "
                            f"eyes, got {self.width}x{self.height}")
        self.eye_size = (self.width // 2, self.height) if sbs else (self.width, self.height // 2)
        self._rest = rest
        self.base_lens = base_cls(*self.eye_size, **rest)
        self.offsets = ((0, 0), (self.eye_size[0], 0)) if sbs else ((0, 0), (0, self.eye_size[1]))

    @property
    def v360_read(self):
        """How ffmpeg's v360 reads each eye: as it reads the base (lenslab.warp.compat_v360)."""
        return getattr(self.base_lens, "v360_read", None)

    def param_values(self) -> dict[str, Any]:
        out = {"layout": self.layout, "base": self.base}
        for k, v in self.base_lens.param_values().items():
            out.setdefault(k, v)
        return out

    def pixels_per_degree(self) -> float:
        return self.base_lens.pixels_per_degree()  # (an eye's: one above the other, each has half the rows)

    def size_note(self) -> str | None:
        note = self.base_lens.size_note()  # (each eye is the base at half the image)
        return note and f"stereo:layout={self.layout}, each eye: {note}"

    def spec(self) -> str:
        _, _, base_params = self.base_lens.spec().partition(":")
        return f"stereo:layout={self.layout},base={self.base}" + ("," + base_params if base_params else "")

    def with_size(self, width: int, height: int) -> "Stereo":
        return Stereo(width, height, layout=self.layout, base=self.base, **self._rest)

    # -- what the engine asks --------------------------------------------------------------------
    def pieces(self):
        """The two eyes, left (top) first: each a piece with ``eye`` 0 or 1 and the base lens at its size."""
        w, h = self.eye_size
        return tuple(Piece(float(x0), float(y0), float(w), float(h), lens=self.base_lens, pose=Pose(), eye=k)
                     for k, (x0, y0) in enumerate(self.offsets))

    def seams(self):
        return self.base_lens.seams() if self.layout == "tb" else super().seams()

    # -- the frame as two copies of the base ---------------------------------------------------------
    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        local = xy.copy()
        w, h = self.eye_size
        with np.errstate(invalid="ignore"):
            second = (xy[..., 0] >= w) if self.layout == "sbs" else (xy[..., 1] >= h)
        axis = 0 if self.layout == "sbs" else 1
        local[..., axis] -= np.where(second, float(self.eye_size[axis]), 0.0)
        d, ok = self.base_lens.pixel_to_dir(local)
        return clean(d, ok & self.in_image(xy), inplace=True)

    def dir_to_pixel(self, dirs):
        xy, ok = self.base_lens.dir_to_pixel(dirs)
        # the edge between the eyes belongs to the second eye: keep the first eye's points off it
        axis = 0 if self.layout == "sbs" else 1
        np.minimum(xy[..., axis], self.eye_size[axis] * (1.0 - 1e-15), out=xy[..., axis])
        return xy, ok

    def source_view_count(self) -> int:
        return self.base_lens.source_view_count()

    def source_views(self, dirs):
        return self.base_lens.source_views(dirs)


__all__ = ["Stereo", "LAYOUTS"]
