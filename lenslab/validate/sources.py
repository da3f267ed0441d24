"""What a validation renders: the ray tracer's scenes, or an analytic environment with no geometry.

A *source* turns a camera into an image: ``source.render(camera, spp, seed) -> Render``. Two kinds:

- ``tracer.validate.source.TracerSource`` (in the tracer package; lenslab never imports it): a scene
  of the ray tracer (e.g. the Cornell box), traced with its ``direct`` or ``path`` integrator. Monte Carlo noise is in the picture unless the tracer is run with
  fixed sample positions (``seed=None``) and a deterministic light (a point light).
- :class:`AnalyticSource`: an environment-only scene whose radiance is a closed-form function of the
  ray direction (a smooth sky, a sharp-edged sun disc and a checker of latitude/longitude cells). A
  pixel's value is the mean of that function over a fixed grid of sub-pixel samples, so the image has
  no noise at all: comparing a warp with it measures resampling error alone.

Both return premultiplied colour (``H x W x 3`` float32), coverage alpha (the fraction of a pixel's
samples whose ray the lens defines), the standard error of each pixel's mean when known, and
geometric AOVs at the pixel centres for finding edges.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lenslab.lenses import Camera


@dataclass
class Render:
    """One rendered image: premultiplied colour, coverage, noise estimate, AOVs and the time it took."""

    image: np.ndarray                 # H x W x 3 float32, premultiplied by alpha
    alpha: np.ndarray                 # H x W float32 in [0, 1]
    stderr: np.ndarray | None = None  # H x W x 3 float32 standard error of each pixel's mean, or None
    aovs: dict[str, np.ndarray] = field(default_factory=dict)  # depth / normal / prim_id (H x W ...)
    seconds: float = 0.0
    spp: int = 1
    info: dict[str, Any] = field(default_factory=dict)


# -- the analytic environment ------------------------------------------------------------------------
SUN_DIR = np.array([0.35, 0.45, 0.82])
SUN_DIR = SUN_DIR / np.linalg.norm(SUN_DIR)
SUN_COS = float(np.cos(np.radians(6.0)))  # a 6 deg angular radius disc
SUN_RADIANCE = np.array([12.0, 10.0, 7.0])
CELL_DEG = 30.0  # checker cell size in longitude and latitude


def sky_radiance(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Radiance (float64 ``(..., 3)``) and region id (int ``(...)``) of unit world directions ``d``.

    ``L(d) = smooth(d) * checker(d) + sun(d)``: a smooth gradient from a dim ground to a bright zenith
    with a gentle longitude ripple; a checker of 30 x 30 deg latitude/longitude cells (factor 1 or 0.4,
    sharp edges); a disc of 6 deg radius and radiance about 10 (a hard bright edge). The region id
    changes exactly where the function jumps, so edges can be found as for a scene's primitive ids.
    """
    d = np.asarray(d, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    phi = np.arctan2(x, z)
    theta = np.arcsin(np.clip(y, -1.0, 1.0))
    base = 0.3 + 0.35 * (y + 1.0) + 0.08 * np.sin(3.0 * phi) * np.cos(theta)
    colour = np.stack([base * 0.9, base, base * 1.15], axis=-1)
    ci = np.floor(np.degrees(phi) / CELL_DEG).astype(np.int64)
    cj = np.floor(np.degrees(theta) / CELL_DEG).astype(np.int64)
    cell = (ci + cj) & 1
    checker = np.where(cell == 1, 0.4, 1.0)
    sun = (d @ SUN_DIR) >= SUN_COS
    rad = colour * checker[..., None] + np.where(sun[..., None], SUN_RADIANCE, 0.0)
    region = np.where(sun, -2, (ci + 12) * 8 + (cj + 4))
    return rad, region


class AnalyticSource:
    """Noise-free renders of :func:`sky_radiance` through any lenslab camera (no geometry, no tracer)."""

    name = "analytic-sky"
    noise_free = True
    shadow_edges = False  # the region ids mark every discontinuity of the radiance

    def __init__(self, band_pixels: int = 1 << 18):
        self.band_pixels = int(band_pixels)

    def render(self, camera: Camera, spp: int = 1, seed: int | None = None) -> Render:
        """Mean of the radiance over ``spp`` sub-pixel samples (strata centres when ``seed`` is None)."""
        t0 = time.perf_counter()
        w, h = camera.size
        img = np.zeros((h, w, 3), dtype=np.float32)
        m2 = np.zeros((h, w, 3), dtype=np.float32)
        alpha = np.zeros((h, w), dtype=np.float32)
        rows = max(1, self.band_pixels // max(1, w * spp))
        for r0 in range(0, h, rows):
            band = slice(r0, min(h, r0 + rows))
            _, dirs, valid = camera.rays(samples=spp, seed=seed, rows=band)
            rad, _ = sky_radiance(dirs)
            rad = np.where(valid[..., None], rad, 0.0)
            img[band] = rad.mean(axis=2)
            m2[band] = (rad ** 2).mean(axis=2)
            alpha[band] = valid.mean(axis=2)
        # pixel centres for the AOVs (region id as the primitive id, -1 where the lens sees nothing)
        centres = camera.pixel_grid(None, 1, None)[:, :, 0]
        _, dirs, valid = camera.pixel_to_world(centres)
        _, region = sky_radiance(dirs)
        region = np.where(valid, region, -1)
        stderr = None
        if seed is not None and spp > 1:  # jittered samples: the spread of the estimate
            var = np.maximum(m2 - img.astype(np.float64) ** 2, 0.0) * spp / (spp - 1)
            stderr = np.sqrt(var / spp).astype(np.float32)
        elif seed is not None:
            stderr = None
        else:
            stderr = np.zeros_like(img)  # fixed sample positions: deterministic, no noise
        return Render(img, alpha, stderr, {"prim_id": region}, time.perf_counter() - t0, spp,
                      {"source": self.name})
