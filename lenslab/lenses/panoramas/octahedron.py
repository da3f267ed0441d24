"""The octahedral map: the whole sphere on a square, ffmpeg v360's ``octahedron``."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Lens, Piece, ReferencePoint
from lenslab.lenses.core.protocol import BOTTOM, LEFT, RIGHT, TOP, Across
from lenslab.lenses.registry import register


@register
class Octahedron(Lens):
    r"""Octahedral map: the sphere projected onto an octahedron, unfolded onto a square.

    A direction is scaled onto the octahedron ``|x| + |y| + |z| = 1``; the front half (``z >= 0``) is the
    diamond ``|u| + |v| <= 1`` with ``(u, v) = (x, y)`` there, and the back half folds out into the four
    corners: ``(u, v) = ((1 - |y|) sign x, (1 - |x|) sign y)``. Inverse: ``z = 1 - |u| - |v|``; where
    ``z < 0``, ``(x, y) = ((1 - |v|) sign u, (1 - |u|) sign v)``, else ``(x, y) = (u, v)``; ``d`` is
    ``(x, y, z)`` normalised. Square frames (on others ``v`` runs over the height's share of the square).
    The square's edges fold onto themselves (each half of an edge onto the other half): the back pole
    is the four corners.
    """

    name = "octahedron"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('octahedron', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('octahedron', (512, 512), (310.85714285714283, 292.57142857142856),
                       (0.30942637387763805, -0.2062842492517587, 0.9282791216329142),
                       'octahedral map (ffmpeg v360 octahedron), front half, float64'),
        ReferencePoint('octahedron', (512, 512), (448.0, 85.33333333333334),
                       (0.5656854249492381, 0.4242640687119285, -0.7071067811865476),
                       'octahedral map (ffmpeg v360 octahedron), back half folded into a corner'),
    )
    summary = "octahedral map: the whole sphere on a square, front in the centre diamond"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 1.0

    def pieces(self):
        """One piece whose edges fold onto themselves: beyond the left edge at height s lies the left
        edge at height H - s (and likewise for the other three)."""
        across = tuple(Across(0, e, True) for e in (LEFT, RIGHT, TOP, BOTTOM))
        return (Piece(0.0, 0.0, float(self.width), float(self.height), across=across),)

    def uv_to_dir(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        au, av = np.abs(u), np.abs(v)
        d = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        z = 1.0 - au - av
        back = z < 0
        d[..., 0] = np.where(back, np.copysign(1.0 - av, u), u)
        d[..., 1] = np.where(back, np.copysign(1.0 - au, v), v)
        d[..., 2] = z
        d /= np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
        return d, (au <= 1.0) & (av <= 1.0)

    def dir_to_uv(self, d):
        s = np.abs(d).sum(axis=-1)
        x, y = d[..., 0] / s, d[..., 1] / s
        back = d[..., 2] < 0
        uv = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        uv[..., 0] = np.where(back, np.copysign(1.0 - np.abs(y), x), x)
        uv[..., 1] = np.where(back, np.copysign(1.0 - np.abs(x), y), y)
        return uv, np.ones(d.shape[:-1], dtype=bool)
