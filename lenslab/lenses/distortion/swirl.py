"""The swirl: a whirlpool twist of the image plane in front of a base model."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Param, PixelKernel, ReferencePoint
from lenslab.lenses.registry import register
from lenslab.lenses.core.wrapped import Wrapped


def rotate_by_radius(uv: np.ndarray, amount: float) -> np.ndarray:
    """Turn each point ``(u, v)`` by ``amount * rho`` radians about the centre (``rho = |(u, v)|``).

    As complex numbers: ``(u + i v) * exp(i amount rho)``.
    """
    uv = np.ascontiguousarray(uv, dtype=FLOAT)
    u, v = uv[..., 0], uv[..., 1]
    k = u * u
    k += v * v
    np.sqrt(k, out=k)
    k *= amount
    w = np.empty(k.shape, dtype=np.complex128)
    w.real = np.cos(k)
    w.imag = np.sin(k)
    w *= uv.view(np.complex128)[..., 0]
    return w.view(FLOAT).reshape(uv.shape)


@register
class Swirl(Wrapped):
    r"""Swirl: each point turns about the centre by an angle growing with its radius.

    In polar coordinates ``(rho, alpha)`` of ``(u, v)``::

        alpha' = alpha + rho * amount      (radians per unit radius; 6.0 is a strong swirl)
        (u', v') = rho (cos alpha', sin alpha')  ->  base model (perspective by default)

    computed as a rotation by ``rho * amount`` (no atan2, exact at ``rho = 0``). The radius is kept,
    so the bend is a bijection of the plane for every amount and the inverse is exact:
    ``alpha = alpha' - rho * amount``. Positive amounts turn counter-clockwise (x right, y up).
    """

    name = "swirl"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('swirl:amount=6', (8192, 4608)),
        ('swirl:amount=-3,base=fisheye,fov=180,mapping=equisolid', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('swirl:amount=6', (640, 480), (420.5, 180.25),
                       (-0.3143367837607204, 0.1377262460019085, 0.9392677294239314),
                       "swirl alpha' = alpha + rho amount (docs/conventions.md), then d ~ (u', v', 1) at fov 90"),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('swirl:amount=2,fov=80', 'swirl:amount=1.5,fov=70', 'amount,fov'),
        ('swirl:amount=3,base=fisheye,fov=190,mapping=equisolid',
         'swirl:amount=2.5,base=fisheye,fov=170,mapping=equisolid', 'amount,fov'),
    )
    summary = "whirlpool twist of the image plane in front of a base model (perspective by default)"
    own_params = (
        Param("amount", 6.0, "twist, radians per unit radius (u = 1 at the right edge); negative turns clockwise"),
    )

    def bend(self, uv):
        return rotate_by_radius(uv, self.amount), np.ones(uv.shape[:-1], dtype=bool)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` of a swirled pinhole (``swirl_pixels``: the NumPy steps of the perspective's
        :meth:`dir_to_uv`, :meth:`unbend` and :meth:`Lens.dir_to_pixel`, in their order); None for other bases."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels
        from lenslab.lenses.projections.perspective import Perspective

        base = self.base_lens
        if type(base) is not Perspective or not kernel_holds(self, Swirl, ("unbend",)):
            return None
        return PixelKernel(lens_kernels().swirl_pixels, np.array(
            [self.width, self.height, self.aspect, base.t, base.tv, -self.amount, self.edge_slack], dtype=FLOAT))

    def unbend(self, uv):
        return rotate_by_radius(uv, -self.amount), np.ones(uv.shape[:-1], dtype=bool)
