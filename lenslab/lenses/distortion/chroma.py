"""Transverse chromatic aberration (TCA) and vignetting for any lens.

TCA follows lensfun: in the image, the red (blue) picture of a point whose green picture lies at
radius ``r`` sits at ``r * P(r)``, ``P(r) = v + c r + b r^2`` (linear: ``P = k``), with ``r`` measured
from the lens centre in units of half the image's shorter side. Each channel is then a lens of its
own (:class:`ChannelLens`): its pixel is moved onto the green picture, then traced by the base lens.

Vignetting is a relative illumination ``falloff(xy)`` (1 on the axis): lensfun's ``pa`` polynomial
``1 + k1 r^2 + k2 r^4 + k3 r^6`` with ``r = 1`` at the image corner, or the natural ``cos^4`` law of a
perspective lens (the fourth power of the cosine of the ray's angle to the optical axis).

The ``optics`` model puts both on any base lens, e.g.
``optics:tca=1.0006/0.9994,vignetting=pa/-0.3/0.1/-0.05,base=perspective,fov=60``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import Lens, Param, ReferencePoint, as_points, clean, normalize
from lenslab.lenses.formulas.radial import Radial, scale_points
from lenslab.lenses.registry import make_lens, register
from lenslab.lenses.core.wrapped import Wrapped, has_uv_maps


def parse_numbers(text: str, what: str, counts: tuple[int, ...]) -> tuple[float, ...]:
    """``"1.0006/0.9994"`` -> floats; the count must be one of ``counts``."""
    parts = [p for p in str(text).replace(" ", "/").split("/") if p]
    try:
        vals = tuple(float(p) for p in parts)
    except ValueError:
        raise LensError(f"{what}: expected numbers separated by '/', got {text!r}") from None
    if len(vals) not in counts or not all(np.isfinite(vals)):
        raise LensError(f"{what}: expected {' or '.join(map(str, counts))} finite numbers separated by '/', got {text!r}")
    return vals


def tca_radials(terms: tuple[float, ...]) -> tuple[Radial, Radial]:
    """Red and blue :class:`Radial` from lensfun's TCA terms: linear ``(kr, kb)`` or poly3
    ``(vr, vb, cr, cb, br, bb)``."""
    if len(terms) == 2:
        return Radial((terms[0],)), Radial((terms[1],))
    vr, vb, cr, cb, br, bb = terms
    return Radial((vr, cr, br)), Radial((vb, cb, bb))


def unbounded_dir_to_pixel(lens: Lens, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions of directions without the image-bounds test (a green picture just outside the
    frame may have its red picture inside)."""
    own = getattr(lens, "dir_to_pixel_unbounded", None)
    if own is not None:
        return own(d)
    if has_uv_maps(type(lens)):
        with np.errstate(all="ignore"):
            uv, valid = lens.dir_to_uv(normalize(as_points(d, 3, "directions")))
            xy = lens.uv_to_pixel(uv)
        return clean(xy, valid, inplace=True)
    return lens.dir_to_pixel(d)


class ChannelLens(Lens):
    """One colour channel of a lens with TCA: ``base`` traces the green picture; this channel's
    picture is the green one scaled radially by ``radial`` about ``centre`` (pixels), with radii in
    units of ``1 / norm`` pixels."""

    name = "channel"

    def __init__(self, base: Lens, centre: tuple[float, float], norm: float, radial: Radial, label: str):
        super().__init__(base.width, base.height)
        self.base, self.centre, self.norm, self.radial, self.label = base, np.asarray(centre, float), norm, radial, label

    def spec(self) -> str:
        return f"{self.base.spec()} [{self.label} channel]"

    def to_dict(self) -> dict[str, Any]:
        return {**self.base.to_dict(), "channel": self.label}

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        q = (xy - self.centre) * self.norm
        qg, ok = scale_points(q, self.radial, invert=True)
        d, valid = self.base.pixel_to_dir(qg / self.norm + self.centre)
        return clean(d, valid & ok, inplace=True)

    def dir_to_pixel_unbounded(self, dirs):
        xyg, valid = unbounded_dir_to_pixel(self.base, dirs)
        q, ok = scale_points((xyg - self.centre) * self.norm, self.radial, invert=False)
        return clean(q / self.norm + self.centre, valid & ok, inplace=True)

    def dir_to_pixel(self, dirs):
        xy, valid = self.dir_to_pixel_unbounded(dirs)
        valid &= self.snap_to_image(xy)
        np.copyto(xy, 0.0, where=~valid[..., None])
        return xy, valid

    def pixel_origin(self, xy):
        return self.base.pixel_origin(xy)

    @property
    def eye_offsets(self):
        return self.base.eye_offsets


def pa_falloff(r: np.ndarray, k: tuple[float, float, float]) -> np.ndarray:
    """lensfun's pa vignetting ``1 + k1 r^2 + k2 r^4 + k3 r^6`` (``r = 1`` at the corner), float64."""
    r2 = r * r
    return 1.0 + r2 * (k[0] + r2 * (k[1] + r2 * k[2]))


def cos4_falloff(lens: Lens, xy: np.ndarray) -> np.ndarray:
    """Natural vignetting ``cos^4`` of the ray's angle to the optical axis (0 behind the camera)."""
    d, valid = lens.pixel_to_dir(xy)
    c = np.clip(d[..., 2], 0.0, 1.0)
    return np.where(valid, c ** 4, 0.0)


@register
class Optics(Lens):
    r"""Chromatic aberration and vignetting on any base lens; the base's parameters pass through.

    ``tca=kr/kb`` (linear) or ``tca=vr/vb/cr/cb/br/bb`` (lensfun's poly3 order): the red (blue)
    picture of a point whose green picture is at radius ``r`` lies at ``r (v + c r + b r^2)``, ``r`` in
    units of half the shorter side from the image centre. ``vignetting=pa/k1/k2/k3``: illumination
    ``1 + k1 r^2 + k2 r^4 + k3 r^6`` with ``r = 1`` at the corner; ``vignetting=cos4``: the natural
    ``cos^4`` of the ray angle. Numbers are separated by ``/`` because ``,`` separates parameters.
    As a destination each channel is traced along its own ray and multiplied by the falloff; as a
    source each channel is sampled at its own position and divided by it (alpha stays one).
    """

    name = "optics"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('optics:tca=1.001/0.999,vignetting=cos4,base=fisheye,fov=180', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('optics:tca=1.001/0.999,vignetting=cos4,base=fisheye,fov=180', (512, 512), (400.25, 130.5),
                       (0.6955870310124869, 0.6051727722153699, 0.38720097889390415),
                       'its base lens (green): equidistant a = r fov/2'),
    )
    summary = "chromatic aberration (TCA) and vignetting on any base lens"
    quiet_defaults = {"tca": "", "vignetting": "none"}  # no effect asked for: left out of the printed spec
    params = (
        Param("base", "perspective", "lens model the effects are put on (its parameters pass through)"),
        Param("tca", "", "red/blue radial scale: kr/kb or vr/vb/cr/cb/br/bb (empty: none)"),
        Param("vignetting", "none", "none, cos4, or pa/k1/k2/k3 (r = 1 at the corner)"),
    )

    def __init__(self, width: int, height: int, **values: Any):
        own = {p.name for p in self.params}
        rest = {k: v for k, v in values.items() if k not in own}
        super().__init__(width, height, **{k: v for k, v in values.items() if k in own})
        if self.base.strip().lower() == self.name:
            raise LensError("optics: base=optics is not allowed; give the effects once")
        self.base_lens = make_lens({"model": self.base, **rest}, (width, height))

    def _check(self) -> None:
        self.tca_terms = parse_numbers(self.tca, "optics: tca", (2, 6)) if str(self.tca).strip() else None
        v = str(self.vignetting).strip().lower()
        if v in ("", "none"):
            self.vig = None
        elif v == "cos4":
            self.vig = "cos4"
        elif v.startswith("pa/"):
            self.vig = parse_numbers(v[3:], "optics: vignetting=pa", (3,))
        else:
            raise LensError(f"optics: vignetting must be none, cos4 or pa/k1/k2/k3, got {self.vignetting!r}")

    # own parameters first, then the base's, as for the bent models
    param_values = Wrapped.param_values
    spec = Wrapped.spec

    # geometry is the base's (the green channel)
    def pixel_to_dir(self, xy):
        return self.base_lens.pixel_to_dir(xy)

    def dir_to_pixel(self, dirs):
        return self.base_lens.dir_to_pixel(dirs)

    def pixel_origin(self, xy):
        return self.base_lens.pixel_origin(xy)

    @property
    def eye_offsets(self):
        return self.base_lens.eye_offsets

    # the rest of the protocol is the base's too: its seams, pieces, compiled map, column scale
    def seams(self):
        return self.base_lens.seams()

    def pieces(self):
        return self.base_lens.pieces()

    def pixel_kernel(self):
        return self.base_lens.pixel_kernel()

    def column_scale(self, y):
        return self.base_lens.column_scale(y)

    def channel_lenses(self):
        if self.tca_terms is None:
            return None
        red, blue = tca_radials(self.tca_terms)
        centre = (self.width / 2.0, self.height / 2.0)
        norm = 2.0 / min(self.width, self.height)
        return (ChannelLens(self.base_lens, centre, norm, red, "red"), self,
                ChannelLens(self.base_lens, centre, norm, blue, "blue"))

    def falloff(self, xy):
        if self.vig is None:
            return None
        xy = as_points(xy, 2, "pixel coordinates")
        if self.vig == "cos4":
            return cos4_falloff(self.base_lens, xy)
        r = np.hypot(xy[..., 0] - self.width / 2.0, xy[..., 1] - self.height / 2.0) / (0.5 * np.hypot(self.width, self.height))
        return pa_falloff(r, self.vig)
