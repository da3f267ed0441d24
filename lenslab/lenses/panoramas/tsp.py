"""The truncated square pyramid (ffmpeg v360's ``tsp``): the front face at full size, the back face
small, the four sides as trapezoids between them, in a frame of two halves."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import Lens, ReferencePoint, as_points, clean
from lenslab.lenses.registry import register

#: lenslab's frame (+y up) -> the frame v360's cube-face formulas use (+y down)
FLIP_Y = np.array([1.0, -1.0, 1.0])


def cube_face(v):
    """v360's cube face of each direction (in its frame) and the face coordinates ``(s, t)`` in [-1, 1]:
    0 right, 1 left, 2 up, 3 down, 4 front, 5 back."""
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    ax, ay, az = np.abs(x), np.abs(y), np.abs(z)
    face = np.where((ax >= ay) & (ax >= az), np.where(x > 0, 0, 1),
                    np.where(ay >= az, np.where(y < 0, 2, 3), np.where(z > 0, 4, 5)))
    with np.errstate(all="ignore"):
        s = np.select([face == 0, face == 1, face == 2, face == 3, face == 4], [-z / x, -z / x, -x / y, x / y, x / z],
                      x / z)
        t = np.select([face == 0, face == 1, face == 2, face == 3, face == 4], [y / x, -y / x, -z / y, -z / y, y / z],
                      -y / z)
    return face, s, t


@register
class TruncatedSquarePyramid(Lens):
    r"""Truncated square pyramid: the front cube face full size, the back face small, sides as trapezoids.

    The front face fills the left half of the frame; the right half holds the back face (a small square, ``W/8 x H/4``, in the middle of the right half's middle band)
    and the four side faces as trapezoids between it and the right half's edges (right face on its
    left, left face on its right, top and bottom faces above and below). Directions go to their cube
    face (``s, t`` in [-1, 1], ``s`` right and ``t`` down across it, as v360's cube faces), then onto
    its part of the frame by v360's bilinear maps of ``(s + 1)/2`` and ``(t + 1)/2``; pixels back to
    directions by their inverses. v360's ``tsp``.
    """

    name = "tsp"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("tsp", (8192, 4096)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): v360's ``xyz_to_cube`` and
    #: ``xyz_to_tspyramid`` in float64 (frame fractions times the size): a side, the top and the back face
    reference_points = (
        ReferencePoint("tsp", (1024, 512), (586.6666666666666, 195.55555555555557),
                       (0.928279121632914, 0.309426373877638, 0.20628424925175867),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_tspyramid (right face), float64"),
        ReferencePoint("tsp", (1024, 512), (743.5, 60.0),
                       (0.1162476387438193, 0.9299811099505544, 0.34874291623145787),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_tspyramid (up face), float64"),
        ReferencePoint("tsp", (1024, 512), (782.2222222222222, 277.3333333333333),
                       (-0.20628424925175867, -0.309426373877638, -0.928279121632914),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_tspyramid (back face), float64"),
    )
    summary = "truncated square pyramid: the front face full size, the back small, the sides trapezoids"
    v360_read = "shift"
    frame_aspect = 2.0

    def pixels_per_degree(self) -> float:
        """The front face's rows over its 90 degrees (the face fills the frame's height; the back is smaller)."""
        return self.height / 90.0

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            x, y = xy[..., 0] / self.width, xy[..., 1] / self.height
            one = np.ones_like(x)
            front = np.stack([4 * x - 1, 2 * y - 1, one], -1)
            back = np.stack([1 - 16 * (x - 0.6875), 8 * (y - 0.375) - 1, -one], -1)
            right = np.stack([one, 2 * (y - 2 * x + 1) / (3 - 4 * x) - 1, 1 - 2 * (x - 0.5) / 0.1875], -1)
            left = np.stack([-one, 2 * (y + 2 * x - 2) / (4 * x - 3) - 1, 2 * (x - 0.8125) / 0.1875 - 1], -1)
            up = np.stack([2 * (1 - x - 0.5 * y) / (0.5 - y) - 1, -one, 2 * (0.375 - y) / 0.375 - 1], -1)
            down = np.stack([2 * (0.5 - x + 0.5 * y) / (y - 0.5) - 1, one, 1 - 2 * (1 - y) / 0.375], -1)
            mid = (y >= 0.375) & (y < 0.625)
            is_back = (x >= 0.6875) & (x < 0.8125) & mid
            is_right = (x >= 0.5) & (x < 0.6875) & (((y < 0.375) & (y >= 2 * (x - 0.5))) | mid
                                                      | ((y >= 0.625) & (y <= 2 * (1 - x))))
            is_left = (x >= 0.8125) & (((y < 0.375) & (x >= 1 - y / 2)) | mid | ((y >= 0.625) & (y <= 2 * x - 1)))
            is_up = (y < 0.375) & ~is_right & ~is_left
            v = np.where((x < 0.5)[..., None], front,
                         np.where(is_back[..., None], back,
                                  np.where(is_right[..., None], right,
                                           np.where(is_left[..., None], left,
                                                    np.where(is_up[..., None], up, down)))))
            d = v * FLIP_Y
            d /= np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
            ok = self.in_image(xy)
        return clean(d, ok, inplace=True)

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            face, s, t = cube_face(d * FLIP_Y)
            u, w = (s + 1) * 0.5, (t + 1) * 0.5
            uf = np.select([face == 2, face == 4, face == 3, face == 1, face == 0],
                           [0.1875 * w - 0.375 * u * w - 0.125 * u + 0.8125, 0.5 * u,
                            1 - 0.1875 * w - 0.5 * u + 0.375 * u * w, 0.1875 * u + 0.8125, 0.1875 * u + 0.5],
                           0.125 * u + 0.6875)
            vf = np.select([face == 2, face == 4, face == 3, face == 1, face == 0],
                           [0.375 - 0.375 * w, w, 1 - 0.375 * w, 0.25 * w + 0.75 * u * w - 0.375 * u + 0.375,
                            0.375 * u - 0.75 * u * w + w], 0.25 * w + 0.375)
            xy = np.stack([uf * self.width, vf * self.height], axis=-1)
            # an infinite component is no ray, though its face ratios come out finite
            ok = np.isfinite(d).all(axis=-1) & np.isfinite(xy).all(axis=-1) & self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)


