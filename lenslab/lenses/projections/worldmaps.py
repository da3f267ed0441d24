"""Whole-sphere equal-area maps: Hammer (Hammer-Aitoff) and sinusoidal.

Both show the full sphere inside a 2:1 frame (longitude ``phi`` from -180 at the left to 180 at the
right, latitude ``theta`` up), with square pixels; on another aspect the map keeps its scale across the
width and the rest of the frame has no rays. References: J. P. Snyder, *Map Projections - A Working
Manual*, USGS Professional Paper 1395 (1987), section 30 (sinusoidal) and J. P. Snyder, *Flattening
the Earth* (1993), p. 130 (Hammer's 1892 projection, after Aitoff).

>>> import numpy as np
>>> from lenslab.lenses import make_lens
>>> lens = make_lens("hammer", (400, 200))
>>> xy, ok = lens.dir_to_pixel([[1.0, 0.0, 0.0]])   # longitude 90 on the equator
>>> round(float(xy[0, 0]), 9)   # x = W/2 (1 + sqrt(2) sin(pi/4) / sqrt(1 + cos(pi/4)) / sqrt(2))
308.239220029
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core import v360
from lenslab.lenses.core.base import FLOAT, Lens, PixelKernel, ReferencePoint
from lenslab.lenses.registry import register

RIM_SLACK = 1e-12  # a direction on the outline comes back a few ulps outside it and must still count


@register
class Hammer(Lens):
    r"""Hammer (Hammer-Aitoff) equal-area projection of the whole sphere into a 2:1 ellipse.

    ::

        z = sqrt(1 + cos(theta) cos(phi/2))
        X = 2 sqrt(2) cos(theta) sin(phi/2) / z,    Y = sqrt(2) sin(theta) / z
        u = X / (2 sqrt(2)),  v = Y / (2 sqrt(2))            (the ellipse u^2 + 4 v^2 <= 1)

    Inverse (Snyder): with ``X = 2 sqrt(2) u``, ``Y = 2 sqrt(2) v``, ``z = sqrt(1 - (X/4)^2 - (Y/2)^2)``,
    ``phi = 2 atan2(z X, 2 (2 z^2 - 1))``, ``theta = asin(z Y)``. The back meridian (phi = +-180) is the
    left and right tips of the ellipse's outline: a direction on it comes back on the right half.
    v360's ``hammer``.
    """

    name = "hammer"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('hammer', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('hammer', (800, 400), (556.79883678343, 258.7039480925533),
                       (0.858464846970514, -0.3894183423086505, 0.3337535935229384),
                       'Hammer projection (Snyder, Flattening the Earth, p. 130), float64'),
    )
    summary = "Hammer-Aitoff: the whole sphere in a 2:1 ellipse, equal-area"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "shift"  # half a pixel off its other projections
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 2.0

    def uv_to_dir(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        q = u * u + 4.0 * v * v
        ok = q <= 1.0 + RIM_SLACK
        z = np.sqrt(np.maximum(1.0 - 0.5 * u * u - 2.0 * v * v, 0.0))  # 1 - (X/4)^2 - (Y/2)^2
        X = 2.0 * np.sqrt(2.0) * u
        Y = 2.0 * np.sqrt(2.0) * v
        phi = 2.0 * np.arctan2(z * X, 2.0 * (2.0 * z * z - 1.0))
        s = np.clip(z * Y, -1.0, 1.0)
        c = np.sqrt(1.0 - s * s)
        d = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        np.multiply(np.sin(phi), c, out=d[..., 0])
        d[..., 1] = s
        np.multiply(np.cos(phi), c, out=d[..., 2])
        return d, ok

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: its formulas carried on outside the ellipse (the longitude
        ``2 atan2`` past +-180 degrees)."""
        return v360.continued(self, xy, lambda uv: (self.uv_to_dir(uv)[0], True))

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``hammer_pixels``: the NumPy steps of :meth:`dir_to_pixel`)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Hammer):
            return None
        return PixelKernel(lens_kernels().hammer_pixels, np.array([self.width, self.height, self.aspect,
                                                                    self.edge_slack], dtype=FLOAT))

    def dir_to_uv(self, d):
        dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
        c = np.hypot(dx, dz)  # cos(theta)
        # c cos(phi/2) and c sin(phi/2) from the half-angle formulas (no atan2, exact on the meridians), without
        # the cancellation of c - dz in front or c + dz behind: with a = c + |dz| and h = sqrt(c / (2 a)), the
        # larger is sqrt(c a / 2) = a h and the smaller sqrt(c (c - |dz|) / 2) = |dx| h (as c - |dz| = dx^2 / a);
        # c cos(phi/2) is the larger in front, c sin(phi/2) (with the sign of dx) behind
        a = np.abs(dz)
        a += c
        with np.errstate(divide="ignore", invalid="ignore"):
            h = np.divide(c, a)
            h *= 0.5
            np.sqrt(h, out=h)
        np.copyto(h, 0.0, where=~(a > 0))  # the poles (c = a = 0): both are 0
        big = a * h
        small = np.abs(dx)
        small *= h
        front = dz >= 0
        cc = np.where(front, big, small)
        cs = np.where(front, small, big)
        np.copysign(cs, dx, out=cs)
        z = cc
        z += 1.0
        np.sqrt(z, out=z)  # sqrt(1 + c cos(phi/2))
        uv = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        np.divide(cs, z, out=uv[..., 0])  # X / (2 sqrt 2) = c sin(phi/2) / z
        z *= 2.0
        np.divide(dy, z, out=uv[..., 1])  # Y / (2 sqrt 2) = sin(theta) / (2 z)
        return uv, np.ones(d.shape[:-1], dtype=bool)


@register
class Sinusoidal(Lens):
    r"""Sinusoidal (Sanson-Flamsteed) equal-area projection of the whole sphere.

    ::

        u = phi cos(theta) / pi,    v = theta / pi

    Inverse: ``theta = v pi``, ``phi = u pi / cos(theta)``, valid where ``|phi| <= pi`` (inside the two
    sine curves); at a pole (cos theta = 0) only ``u = 0`` has a ray. v360's ``sinusoidal``.
    """

    name = "sinusoidal"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('sinusoidal', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('sinusoidal', (800, 400), (540.7277536813059, 250.9295817894065),
                       (0.858464846970514, -0.3894183423086505, 0.3337535935229384),
                       'sinusoidal projection (Snyder 1987, section 30), float64'),
    )
    summary = "sinusoidal: the whole sphere between two sine curves, equal-area"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 2.0

    def uv_to_dir(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        theta = v * np.pi
        ok = np.abs(theta) <= np.pi / 2 * (1.0 + RIM_SLACK)
        theta = np.clip(theta, -np.pi / 2, np.pi / 2)
        c = np.cos(theta)
        pole = c < 1e-15
        phi = np.divide(u * np.pi, c, out=np.zeros_like(u), where=~pole)
        ok &= np.abs(phi) <= np.pi * (1.0 + RIM_SLACK)
        ok &= ~pole | (np.abs(u) <= 1e-12)
        d = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        np.multiply(np.sin(phi), c, out=d[..., 0])
        np.sin(theta, out=d[..., 1])
        np.multiply(np.cos(phi), c, out=d[..., 2])
        return d, ok

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: its formulas carried on outside the sine curves (the longitude
        past +-180 degrees)."""
        return v360.continued(self, xy, lambda uv: (self.uv_to_dir(uv)[0], True))

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``sinusoidal_pixels``: the NumPy steps of :meth:`dir_to_pixel`)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Sinusoidal):
            return None
        return PixelKernel(lens_kernels().sinusoidal_pixels, np.array([self.width, self.height, self.aspect,
                                                                        self.edge_slack], dtype=FLOAT))

    def dir_to_uv(self, d):
        dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
        c = np.hypot(dx, dz)
        phi = np.arctan2(dx, dz)
        theta = np.arctan2(dy, c)
        uv = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        np.multiply(phi, c, out=uv[..., 0])  # cos(theta) = c for a unit direction
        uv[..., 0] /= np.pi
        np.divide(theta, np.pi, out=uv[..., 1])
        return uv, np.ones(d.shape[:-1], dtype=bool)
