"""Facebook's barrel layouts of the whole sphere (ffmpeg v360's ``barrel``/``fb`` and ``barrelsplit``)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Lens, Piece, ReferencePoint, as_points, clean
from lenslab.lenses.registry import register

#: the share of each part the picture fills (a 1% margin round it): v360's (and Facebook's) 0.99
SCALE = 0.99
QUARTER = np.pi / 4


def _band_dir(phi, theta):
    """Direction at longitude ``phi`` (0 forward, positive right) and latitude ``theta`` (positive up)."""
    return np.stack([np.cos(theta) * np.sin(phi), np.sin(theta), np.cos(theta) * np.cos(phi)], axis=-1)


def _unit(v):
    """``v`` over its length; NaN for a zero or non-finite vector (the callers mark those invalid)."""
    with np.errstate(all="ignore"):
        return v / np.sqrt(np.einsum("...i,...i->...", v, v))[..., None]


@register
class Barrel(Lens):
    r"""Facebook's barrel: a band of latitudes within 45 degrees and the two caps as cube faces (5:2).

    The equirect band of the latitudes -45..45 degrees fills the left four fifths, the top cap (the up
    face of a cube) the top half and the bottom cap (the down face) the bottom half of the last fifth.
    Each part fills 99% of its rectangle about its centre.

    Band (``W_b = 4W/5``): ``phi = (2x/W_b - 1) pi / 0.99``, ``theta = (1 - 2y/H) (pi/4) / 0.99``.
    Caps (``w = W/5``, ``h = H/2``, ``s = (2 (x - 4w)/w - 1) / 0.99``, ``t = (2 y'/h - 1) / 0.99`` with ``y'``
    from the cap's top): the top cap ``d ~ (s, 1, t)`` (the back at its top), the bottom cap
    ``d ~ (s, -1, -t)`` (the front at its top). A direction with latitude within 45 degrees is read from
    the band, others from their cap. v360's ``barrel`` (``fb``); lenslab's own ``barrel`` is the radial distortion.
    """

    name = "fb-barrel"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("fb-barrel", (8192, 8192 * 2 // 5)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): v360's ``xyz_to_barrel`` in
    #: float64 (its frame coordinates taken as lenslab's continuous pixel): the band and both caps
    reference_points = (
        ReferencePoint("fb-barrel", (1000, 400), (737.5568874104284, 118.41529695841217),
                       (0.42399915200254396, 0.3179993640019079, -0.8479983040050879),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrel (band), float64"),
        ReferencePoint("fb-barrel", (1000, 400), (933.0, 122.0),
                       (0.309426373877638, 0.928279121632914, 0.20628424925175867),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrel (top cap), float64"),
        ReferencePoint("fb-barrel", (1000, 400), (878.0, 267.0),
                       (-0.20628424925175867, -0.928279121632914, 0.309426373877638),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrel (bottom cap), float64"),
    )
    summary = "Facebook's barrel: an equirect band of +-45 degrees and the two caps as cube faces (5:2)"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "shift"
    frame_aspect = 2.5

    def _parts(self):
        w, h = self.width, self.height
        return (0.0, 0.0, 4.0 * w / 5.0, float(h)), (4.0 * w / 5.0, 0.0, w / 5.0, h / 2.0), \
            (4.0 * w / 5.0, h / 2.0, w / 5.0, h / 2.0)

    def pieces(self):
        return tuple(Piece(*r) for r in self._parts())

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        (_, _, bw, bh), (cx0, _, cw, ch), _ = self._parts()
        x, y = xy[..., 0], xy[..., 1]
        with np.errstate(all="ignore"):
            band = _band_dir((2.0 * x / bw - 1.0) * np.pi / SCALE, (1.0 - 2.0 * y / bh) * QUARTER / SCALE)
            s = (2.0 * (x - cx0) / cw - 1.0) / SCALE
            top = y < ch
            t = (2.0 * np.where(top, y, y - ch) / ch - 1.0) / SCALE
            one = np.ones_like(s)
            up = np.stack([s, one, t], axis=-1)
            down = np.stack([s, -one, -t], axis=-1)
            cap = _unit(np.where(top[..., None], up, down))
            d = np.where((x < cx0)[..., None], band, cap)
            ok = self.in_image(xy)
        return clean(d, ok, inplace=True)

    def dir_to_pixel(self, dirs):
        d = _unit(as_points(dirs, 3, "directions"))
        (_, _, bw, bh), (cx0, _, cw, ch), _ = self._parts()
        with np.errstate(all="ignore"):
            phi = np.arctan2(d[..., 0], d[..., 2])
            theta = np.arcsin(np.clip(d[..., 1], -1.0, 1.0))
            in_band = np.abs(theta) < QUARTER
            bx = (phi / np.pi * SCALE + 1.0) * bw / 2.0
            by = (1.0 - theta / QUARTER * SCALE) * bh / 2.0
            up = theta >= 0
            s = np.where(up, d[..., 0] / d[..., 1], -d[..., 0] / d[..., 1])
            t = d[..., 2] / d[..., 1]
            cx = cx0 + 0.5 * cw * (s * SCALE + 1.0)
            cy = np.where(up, 0.0, ch) + 0.5 * ch * (t * SCALE + 1.0)
            xy = np.stack([np.where(in_band, bx, cx), np.where(in_band, by, cy)], axis=-1)
            ok = np.isfinite(xy).all(axis=-1) & self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)


def _v360(d):
    """lenslab's frame (+y up) -> the frame v360's barrel-split formulas use (+y down)."""
    return d * np.array([1.0, -1.0, 1.0])


@register
class BarrelSplit(Lens):
    r"""Facebook's split barrel: the band as front and back halves, the caps cut in halves (3:2).

    The latitudes -45..45 degrees are two equirect halves on the left two thirds (the front half,
    longitudes -90..90, on top; the back half, 90..270, below), and the two caps are cut into front and
    back halves, stacked in the right third (top cap front half, bottom cap
    front half, top cap back half, bottom cap back half; each ``W/3 x H/4``, each half a cube face
    stretched to the quarter's full height).

    Band: ``phi = (3x/2W - 1/2 - b) pi``, ``theta = (1/4 + b/2 - y/H) pi`` with ``b`` = 0 on top, 1 below.
    Quarters: with ``s = 3x/W - 2`` and ``q = 4y/H - k`` in [0, 1) in quarter ``k``, in v360's frame
    (``y`` down): ``(s - 1/2, -1/2, q/2)``, ``(s - 1/2, 1/2, (1 - q)/2)``, ``(1/2 - s, -1/2, -q/2)``,
    ``(1/2 - s, 1/2, (q - 1)/2)``. v360's ``barrelsplit``.
    """

    name = "fb-barrelsplit"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("fb-barrelsplit", (8192, 8192 * 2 // 3)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): v360's ``xyz_to_barrelsplit``
    #: in float64 with no pad (its frame coordinates taken as lenslab's continuous pixel)
    reference_points = (
        ReferencePoint("fb-barrelsplit", (960, 640), (414.4535152962773, 94.07296723912096),
                       (0.42399915200254396, 0.3179993640019079, 0.8479983040050879),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrelsplit (front half), float64"),
        ReferencePoint("fb-barrelsplit", (960, 640), (446.3561877047978, 526.5368038607405),
                       (-0.5661385170722979, -0.22645540682891915, -0.792593923901217),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrelsplit (back half), float64"),
        ReferencePoint("fb-barrelsplit", (960, 640), (853.3333333333333, 35.55555555555557),
                       (0.309426373877638, 0.928279121632914, 0.20628424925175867),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrelsplit (top cap, front), float64"),
        ReferencePoint("fb-barrelsplit", (960, 640), (835.5555555555555, 586.6666666666667),
                       (-0.20628424925175867, -0.928279121632914, -0.309426373877638),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_barrelsplit (bottom cap, back), float64"),
    )
    summary = "Facebook's split barrel: two equirect halves of +-45 degrees and the caps in four halves (3:2)"
    v360_read = "shift"
    frame_aspect = 1.5

    def _rects(self):
        w, h = float(self.width), float(self.height)
        return [(0.0, 0.0, 2 * w / 3, h / 2), (0.0, h / 2, 2 * w / 3, h / 2)] + \
            [(2 * w / 3, k * h / 4, w / 3, h / 4) for k in range(4)]

    def pieces(self):
        return tuple(Piece(*r) for r in self._rects())

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            x, y = xy[..., 0] / self.width, xy[..., 1] / self.height
            back = np.floor(np.clip(y * 2.0, 0.0, 1.0))
            band = _band_dir((1.5 * x - 0.5 - back) * np.pi, (0.25 + 0.5 * back - y) * np.pi)
            s = 3.0 * x - 2.0
            k = np.clip(np.floor(y * 4.0), 0, 3)
            q = 4.0 * y - k
            half = np.full(s.shape, 0.5)
            faces = [np.stack([s - 0.5, -half, q / 2], -1), np.stack([s - 0.5, half, (1 - q) / 2], -1),
                     np.stack([0.5 - s, -half, -q / 2], -1), np.stack([0.5 - s, half, (q - 1) / 2], -1)]
            cap = faces[0]
            for j in (1, 2, 3):
                cap = np.where((k == j)[..., None], faces[j], cap)
            d = np.where((x < 2.0 / 3.0)[..., None], band, _unit(_v360(cap)))
            ok = self.in_image(xy)
        return clean(d, ok, inplace=True)

    def dir_to_pixel(self, dirs):
        d = _unit(as_points(dirs, 3, "directions"))
        v = _v360(d)
        w, h = float(self.width), float(self.height)
        with np.errstate(all="ignore"):
            phi = np.arctan2(v[..., 0], v[..., 2])
            theta = np.arcsin(np.clip(v[..., 1], -1.0, 1.0))
            in_band = np.abs(theta) <= QUARTER
            back = (phi >= np.pi / 2) | (phi < -np.pi / 2)
            # the front half shows phi in [-90, 90), the back half phi - 360 in [-270, -90) degrees
            bx = w * np.where(back, np.where(phi >= 0, phi - 2 * np.pi, phi) / (1.5 * np.pi) + 1.0,
                              phi / (1.5 * np.pi) + 1.0 / 3.0)
            by = (theta / QUARTER + 1.0) * h / 4.0 + np.where(back, h / 2, 0.0)
            x_, y_, z_ = v[..., 0], v[..., 1], v[..., 2]
            front = np.abs(phi) <= np.pi / 2
            up = theta <= 0
            cs = np.where(up & front, -x_ / y_, np.where(front, x_ / y_, np.where(up, x_ / y_, -x_ / y_)))
            ct = np.where(up & front, -z_ / y_, np.where(front, -z_ / y_, z_ / y_))
            shift = np.where(up & front, 0.0, np.where(front, h / 4, np.where(up, h / 2, 3 * h / 4)))
            offset = np.where(up, -h / 4, 0.0)
            cx = 2 * w / 3 + 0.5 * w / 3 * (cs + 1.0)
            cy = shift + h / 4 * (ct + 1.0) + offset
            # a quarter's (a half's) lower edge belongs to the part below: keep its own points off it
            cy = np.where(shift + h / 4 < h, np.minimum(cy, (shift + h / 4) * (1.0 - 1e-15)), cy)
            by = np.where(back, by, np.minimum(by, h / 2 * (1.0 - 1e-15)))
            bx = np.minimum(bx, 2 * w / 3 * (1.0 - 1e-15))
            xy = np.stack([np.where(in_band, bx, cx), np.where(in_band, by, cy)], axis=-1)
            ok = np.isfinite(xy).all(axis=-1) & self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)
