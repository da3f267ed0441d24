"""Whether a warp shrinks its source anywhere: what ``--antialias`` is for.

The footprint filter (:mod:`lenslab.warp.antialias`) averages the bilinear reconstruction over each output pixel's
whole footprint. Where the footprint is at most about one source pixel (a same-size or enlarged view) that
average is a small blur and nothing aliases to remove: an identity warp weighs each texel 9/16, its four side
neighbours 3/32 and its corners 1/64, as dense supersampling does. A plan drawn with the filter looks at its
footprints as it draws them (:func:`watch`), and :func:`shrinks` then says whether any pixel's footprint is
longer than :data:`SHRINK` source pixels in some direction.

The test is exact and cheap: the larger singular value of each footprint's Jacobian, from its sides' lengths and
cross product in a few float32 passes (2.7 ms for a band of 262,144 footprints, load 4.3); once one band shrinks the
source, the plan's other bands are not looked at, and a kept band (a batch's, a clip's) is looked at once. A warp
by a given map (an ST map: :func:`lenslab.warp.warp_with_map`) has no plan: its footprints, from the differences
between neighbouring map entries, are looked at the same way for a :class:`Looked` it is given.
"""

from __future__ import annotations

import numpy as np

#: a footprint at most this long (source pixels) in every direction does not shrink the source: one pixel, with
#: room for the map lattice's interpolation (within 1/100 pixel at each end of a side) and a slight shrink
SHRINK = 1.05

#: the note for a warp with --antialias that shrinks its source nowhere (the user's words: see ``lenslab warp -h``)
NOTE = ("--antialias averages each output pixel's whole area, and this view shrinks the source nowhere (no output "
        "pixel covers more than about one source pixel), so it only softens the image: use --antialias where the "
        "output shrinks the source")


def band_shrinks(foot: np.ndarray, valid: np.ndarray) -> bool:
    """Whether any valid footprint of ``foot`` (..., 4) float32 (sides ``a = foot[..., 0:2]``, ``b = foot[..., 2:4]``
    in source pixels; ``valid`` (...) bool) stretches some direction to more than :data:`SHRINK` source pixels: the
    larger singular value of its Jacobian ``J = [a b]`` exceeds it. With ``T = |a|^2 + |b|^2`` and ``D = a x b``,
    ``J^T J``'s eigenvalues sum to ``T`` and multiply to ``D^2``; both are at most ``s^2`` exactly when
    ``T <= 2 s^2`` and ``s^4 - s^2 T + D^2 >= 0``. NaN sides count as not shrinking."""
    f = foot.reshape(-1, 4)
    a0, a1, b0, b1 = f[:, 0], f[:, 1], f[:, 2], f[:, 3]
    s2 = np.float32(SHRINK * SHRINK)
    t = a0 * a0
    t += a1 * a1
    t += b0 * b0
    t += b1 * b1
    d = a0 * b1
    d -= a1 * b0
    d *= d
    out = t > 2 * s2
    d -= s2 * t
    d += s2 * s2
    out |= d < 0
    out &= valid.reshape(-1)
    return bool(out.any())


class Looked:
    """What a warp by a given map (no plan, no pieces or channels of its own) saw of its footprint bands:
    :func:`watch` records on it as on a plan, and :func:`shrinks` answers for it."""

    parts = None
    channels = None


def watch(plan, band) -> None:
    """Look at the footprints of ``band`` (a :class:`~lenslab.warp.antialias.FootprintBand` that ``plan`` draws)
    until a band of the plan is found to shrink the source; a kept band is looked at once."""
    plan._looked = True
    if getattr(plan, "_shrinks", False) or getattr(band, "shrinks", None) is not None:
        return
    band.shrinks = band_shrinks(band.foot, band.valid)
    if band.shrinks:
        plan._shrinks = True


def shrinks(plan) -> bool | None:
    """Whether a plan drawn with the footprint filter shrinks its source anywhere (its pieces' and channels'
    plans included); None when it has not drawn an image with the filter yet."""
    subs = [p for _, _, p, _ in plan.parts] if plan.parts is not None else plan.channels
    if subs is not None:
        got = [shrinks(p) for p in subs]
        return None if None in got else any(got)
    if not getattr(plan, "_looked", False):
        return None
    return bool(getattr(plan, "_shrinks", False))


__all__ = ["SHRINK", "NOTE", "band_shrinks", "Looked", "watch", "shrinks"]
