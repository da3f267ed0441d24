"""Real lenses from the lensfun database: projection, distortion, TCA and vignetting.

``lensfun:lens=samyang 8mm,camera=canon eos 600d,focal=8,aperture=5.6`` is the lens lensfun
knows under that name, on that camera (or ``crop=1.6`` instead of a camera), at those settings.
Values cannot hold a comma unless quoted: ``lens="Canon DIGITAL IXUS 400 & compatibles, with ..."``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import Lens, Param, ReferencePoint, as_points, clean, normalize
from lenslab.lenses.distortion.chroma import ChannelLens, pa_falloff, tca_radials
from lenslab.lenses.formulas import azimuthal, kinds, lonlat
from lenslab.lenses.formulas.radial import R_LIMIT, Radial, scale_points
from lenslab.lenses.registry import register

EFFECTS = ("distortion", "tca", "vignetting")
#: half the diagonal of a 36 x 24 mm frame: lensfun's unit for crop factors
HALF_DIAGONAL_MM = math.hypot(36.0, 24.0) / 2.0


@dataclass(frozen=True)
class Profile:
    """A lens profile resolved at one focal length, aperture and distance (lensfun's numbers)."""

    maker: str
    model: str
    type: str  # rectilinear, fisheye, equisolid, ...
    cal_crop: float  # crop factor of the calibration sensor
    aspect: float  # its aspect ratio (long / short)
    centre: tuple[float, float]  # lens centre offset, lensfun normalised units
    crop: float  # crop factor of the image's sensor
    focal: float  # nominal focal length, mm
    real_focal: float  # the focal length the projection uses, mm
    distortion: tuple[str, tuple[float, ...]] | None
    tca: tuple[str, tuple[float, ...]] | None
    vignetting: tuple[float, float, float] | None


def distortion_radial(model: str, k: tuple[float, ...]) -> Radial:
    """lensfun's distortion models as ``r_d = r_u P(r_u)``."""
    if model == "poly3":
        return Radial((1.0 - k[0], 0.0, k[0]))
    if model == "poly5":
        return Radial((1.0, 0.0, k[0], 0.0, k[1]))
    if model == "ptlens":
        a, b, c = k[:3]
        return Radial((1.0 - a - b - c, c, b, a))
    raise LensError(f"lensfun: distortion model {model} is not supported")


def hugin_focal_correction(dist) -> float:
    """lensfun's correction for Hugin's focal length in poly3 and ptlens calibrations."""
    if dist is None:
        return 1.0
    model, k = dist
    if model == "poly3":
        return 1.0 - k[0]
    if model == "ptlens":
        return 1.0 - k[0] - k[1] - k[2]
    return 1.0


@functools.lru_cache(maxsize=64)
def resolve(lens: str, camera: str, crop: float, focal: float, aperture: float, distance: float,
            _db: tuple) -> Profile:
    """Look the lens up and interpolate its calibrations (lensfunpy), cached per settings and per
    database (``_db``: :func:`lenslab.lenses.lensfun.database.settings`)."""
    from lenslab.lenses.lensfun import database as ldb

    cam = ldb.pick_camera(camera) if camera else None
    lf_lens = ldb.pick_lens(lens, cam)
    if not crop:
        crop = float(cam.crop_factor) if cam is not None else float(lf_lens.crop_factor)
    focal = focal or float(lf_lens.min_focal or 0.0)
    if not focal:
        raise LensError(f"lensfun: {lf_lens.model} has no focal length in the database; give focal=")
    aperture = aperture or float(lf_lens.min_aperture or 0.0)
    dist = tca = vig = None
    d = lf_lens.interpolate_distortion(focal) if lf_lens.calib_distortion else None
    if d is not None and d.model.name.lower() in ("poly3", "poly5", "ptlens"):
        n = {"poly3": 1, "poly5": 2, "ptlens": 3}[d.model.name.lower()]
        dist = (d.model.name.lower(), tuple(float(x) for x in list(d.terms)[:n]))
    t = lf_lens.interpolate_tca(focal) if lf_lens.calib_tca else None
    if t is not None and t.model.name.lower() in ("linear", "poly3"):
        n = 2 if t.model.name.lower() == "linear" else 6
        tca = (t.model.name.lower(), tuple(float(x) for x in list(t.terms)[:n]))
    if lf_lens.calib_vignetting and aperture:
        v = lf_lens.interpolate_vignetting(focal, aperture, distance)
        if v is not None and v.model.name.lower() == "pa":
            vig = tuple(float(x) for x in list(v.terms)[:3])
    facts = ldb.xml_facts(lf_lens.maker, lf_lens.model, float(lf_lens.crop_factor))
    real = ldb.interpolate_real_focal(facts.real_focal, focal)
    # lensfun: the projection's focal is the real one over Hugin's correction, else the nominal one
    real_focal = real / hugin_focal_correction(dist) if real else focal
    type_name = ldb.TYPES.get(lf_lens.type.name)
    if type_name is None:
        raise LensError(f"lensfun: {lf_lens.model} has an unknown projection type")
    return Profile(lf_lens.maker, lf_lens.model, type_name, float(lf_lens.crop_factor), facts.aspect,
                   (float(lf_lens.center_x), float(lf_lens.center_y)), float(crop), float(focal),
                   float(real_focal), dist, tca, vig)


# -- the projections, on lensfun's normalised plane (unit = ``f``), y up -----------------------------
def plane_to_dir(kind: str, x: np.ndarray, y: np.ndarray, f: float) -> tuple[np.ndarray, np.ndarray]:
    """Undistorted plane point -> unit direction (float64) and validity, for lensfun's ``type``."""
    if kind == "rectilinear":
        return normalize(np.stack([x, y, np.full_like(x, f)], -1)), np.ones(x.shape, bool)
    if kind in ("equirectangular", "panoramic"):  # longitude across; latitude, or tan(latitude), up
        lon = x / f
        s, c, ok = lonlat.height_to_lat(kinds.LENSFUN[kind], y / f)
        return lonlat.lonlat_to_dir(lon, s, c), ok & (np.abs(lon) <= np.pi)
    if kind not in kinds.LENSFUN:
        raise LensError(f"lensfun: projection {kind} is not supported")
    return azimuthal.plane_to_dir(kinds.LENSFUN[kind], x / f, y / f)


def parse_effects(text: str) -> tuple[str, ...]:
    words = [w.strip().lower() for w in str(text).replace("+", ",").replace("/", ",").split(",") if w.strip()]
    if words == ["all"]:
        return EFFECTS
    if words == ["none"]:
        return ()
    bad = sorted(set(words) - set(EFFECTS))
    if bad:
        raise LensError(f"lensfun: unknown effect(s) {', '.join(bad)}; valid: all, none, {', '.join(EFFECTS)}")
    return tuple(e for e in EFFECTS if e in words)


@register
class LensfunLens(Lens):
    r"""A real lens from the lensfun database, with its distortion, TCA and vignetting.

    lensfun's conventions throughout: pixel centres at integers, the centre at ``((W-1)/2, (H-1)/2)``
    plus the profile's offset; distortion and TCA radii in units of half the shorter side (spanning
    ``min(W-1, H-1)``), rescaled to the calibration sensor by the crop factors and aspect ratios;
    vignetting radii ``r = 1`` at the calibration sensor's corner. The photo's point at radius ``r_d``
    was ``r_u`` undistorted, ``r_d = r_u P(r_u)`` (poly3, poly5, ptlens); the undistorted plane is the
    profile's projection (``type``) with the real focal length. Red and blue pictures lie at
    ``r (v + c r + b r^2)`` of the green one; the illumination is ``1 + k1 r^2 + k2 r^4 + k3 r^6``.
    Coefficients are interpolated between calibrations by lensfun itself (lensfunpy).
    ``effects`` picks which of ``distortion+tca+vignetting`` apply (``+`` joins them; default all
    the profile has). Quote a value holding a comma: ``lens="..., ..."``.
    """

    name = "lensfun"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=10', (8192, 5461)),
        ('lensfun:lens=Canon EF 70-300mm f/4.5-5.6 DO IS USM,focal=120', (8192, 5461)),
        ('lensfun:lens=Canon PowerShot G12 & compatibles (Standard),focal=10', (8192, 6144)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('lensfun:lens=Canon EF 70-300mm f/4.5-5.6 DO IS USM,focal=120,effects=distortion',
                       (1200, 800), (900.052001953125, 200.79742431640625),
                       (0.07489284874873649, 0.0497208762907585, 0.9959512516519962),
                       'lensfunpy 1.18.0 (lensfun 0.3.4) Modifier.apply_geometry_distortion, one point, to a '
                       'rectilinear target (float32 positions: 1e-4 px)', tolerance=1e-4),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('lensfun:lens=Canon EF 70-300mm f/4.5-5.6 DO IS USM,focal=120',
         'lensfun:lens=Canon EF 70-300mm f/4.5-5.6 DO IS USM,focal=100', 'focal'),
    )
    summary = "a real lens from the lensfun database (distortion, TCA, vignetting)"
    params = (
        Param("lens", "", "lens name or words of it, as lensfun searches (see lenslab lenses --lensfun)"),
        Param("camera", "", "camera name or words of it (sets the crop factor and the mount)"),
        Param("crop", 0.0, "crop factor of the image's sensor (0: the camera's, else the profile's)", 0.0, None),
        Param("focal", 0.0, "focal length, mm (0: the lens's shortest)", 0.0, None),
        Param("aperture", 0.0, "f-number for vignetting (0: the lens's widest)", 0.0, None),
        Param("distance", 1000.0, "focus distance, m", 0.0, None, lo_open=True),
        Param("effects", "all", "distortion+tca+vignetting, all or none"),
    )

    def _check(self) -> None:
        if not self.lens.strip():
            raise LensError("lensfun: give lens=NAME (see lenslab lenses --lensfun \"WORDS\")")
        if self.lens.strip().lower() == "auto":
            raise LensError("lensfun:auto reads the lens from a photo's metadata: give it as the --from of a "
                            "command that reads one (warp), or give lens=NAME")
        from lenslab.lenses.lensfun import database as ldb

        self.profile = p = resolve(self.lens.strip(), self.camera.strip(), self.crop, self.focal,
                                   self.aperture, self.distance, ldb.settings())
        self.active = parse_effects(self.effects)
        explicit = str(self.effects).strip().lower() != "all"
        have = {"distortion": p.distortion, "tca": p.tca, "vignetting": p.vignetting}
        missing = [e for e in self.active if have[e] is None]
        if explicit and missing:
            raise LensError(f"lensfun: {p.maker} {p.model} has no {' or '.join(missing)} data at these settings")
        self.active = tuple(e for e in self.active if have[e] is not None)
        # lensfun's normalisation (modifier.cpp): spans between the outermost pixel centres
        w, h = max(self.width - 1, 1), max(self.height - 1, 1)
        size = min(w, h)
        image_aspect = max(w, h) / size
        arc = math.hypot(p.aspect, 1.0)
        coord = arc / math.hypot(image_aspect, 1.0) * p.cal_crop / p.crop
        self.norm = 2.0 / size * coord  # normalised units per pixel
        self.arc = arc
        self.centre = np.array([w / 2 + p.centre[0] * size / 2 + 0.5, h / 2 + p.centre[1] * size / 2 + 0.5])
        self.f = p.real_focal / (HALF_DIAGONAL_MM / arc / p.cal_crop)  # focal in normalised units
        self.dist = distortion_radial(*p.distortion) if "distortion" in self.active else None

    def default_frame(self, rows: int) -> tuple[int, int]:
        """Its own frame ``rows`` high, where no size is given: the calibration sensor's shape, landscape, long side
        over short the profile's aspect ratio (lensfun's ``aspect-ratio``, 1.5 where the profile gives none)."""
        aspect = max(self.profile.aspect, 1.0 / self.profile.aspect)
        return max(1, round(rows * aspect)), rows

    def spec(self) -> str:
        """Only the values that differ from the defaults; a value holding a comma is quoted."""
        parts = []
        for p in self.params:
            val = getattr(self, p.name)
            if val == p.default:
                continue
            text = f"{val:g}" if isinstance(val, float) else str(val)
            parts.append(f'{p.name}="{text}"' if "," in text else f"{p.name}={text}")
        return self.name + ":" + ",".join(parts)

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        q = (xy - self.centre) * self.norm
        ok = np.isfinite(q).all(-1)
        q = np.where(ok[..., None], q, 0.0)
        if self.dist is not None:
            q, ok2 = scale_points(q, self.dist, invert=True)
            ok &= ok2
        d, valid = plane_to_dir(self.profile.type, q[..., 0], -q[..., 1], self.f)
        return clean(d, valid & ok, inplace=True)

    def dir_to_pixel_unbounded(self, dirs):
        """Pixels of directions, not tested against the image bounds (compiled: one pass)."""
        from lenslab.lenses.core.native import lens_kernels, run_rows

        d = as_points(dirs, 3, "directions")
        if self.dist is not None:
            coeffs, r_lim = self.dist.coeffs, min(self.dist.r_max, R_LIMIT)
        else:
            coeffs, r_lim = np.ones(1), np.inf
        return run_rows(d, 2, lambda flat, out, valid: lens_kernels().lensfun_dir_to_pixel(
            flat, kinds.LENSFUN[self.profile.type], self.f, np.ascontiguousarray(coeffs, dtype=np.float64), float(r_lim),
            float(self.centre[0]), float(self.centre[1]), float(self.norm), out, valid))

    def dir_to_pixel(self, dirs):
        xy, valid = self.dir_to_pixel_unbounded(dirs)
        valid &= self.snap_to_image(xy)
        np.copyto(xy, 0.0, where=~valid[..., None])
        return xy, valid

    def channel_lenses(self):
        if "tca" not in self.active:
            return None
        red, blue = tca_radials(self.profile.tca[1])
        return (ChannelLens(self, self.centre, self.norm, red, "red"), self,
                ChannelLens(self, self.centre, self.norm, blue, "blue"))

    def falloff(self, xy):
        if "vignetting" not in self.active:
            return None
        xy = as_points(xy, 2, "pixel coordinates")
        r = np.hypot(xy[..., 0] - self.centre[0], xy[..., 1] - self.centre[1]) * (self.norm / self.arc)
        return pa_falloff(r, self.profile.vignetting)
