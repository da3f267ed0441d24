"""What a validation renders: the ray tracer's scenes, or an analytic environment with no geometry.

A *source* turns a camera into an image: ``source.render(camera, spp, seed) -> Render``. Two kinds:

- :class:`TracerSource`: a scene of the ``tracer`` package (e.g. the Cornell box), traced with its
  ``direct`` or ``path`` integrator. Monte Carlo noise is in the picture unless the tracer is run with
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


# -- the ray tracer ----------------------------------------------------------------------------------
class TracerSource:
    """A scene of the ``tracer`` package rendered with one of its integrators."""

    noise_free = False
    shadow_edges = False  # shadow edges come from the light-visibility bits of the prim_id AOV

    def __init__(self, scene: str = "cornell", integrator: str = "path", max_depth: int = 8,
                 noise_free: bool = False, point_light_drop: float = 0.0, **render_options):
        import tracer  # the validation command is about tracing: the tracer is imported here only

        self.tracer = tracer
        self.scene_name = scene
        self.scene = tracer.load_scene(scene)
        self.integrator = integrator
        self.max_depth = int(max_depth)
        self.noise_free = bool(noise_free)
        self.render_options = render_options
        self.name = f"{scene} ({integrator}, depth {max_depth})"
        self.point_light_drop = 0.0
        if point_light_drop and len(getattr(self.scene, "point_lights", ())):
            self._lower_point_lights(float(point_light_drop))
            self.name += f", point light lowered {point_light_drop:g}"

    def _lower_point_lights(self, drop: float) -> None:
        """Move the point lights down by ``drop`` scene units (this source's copy of the scene only).

        A point light just under a diffuse ceiling lights a tiny spot of it hundreds of times brighter
        than the rest of the image; that singular spot, not the lens, would then set every error
        figure. Lowered, it lights the ceiling smoothly and still casts hard shadows.
        """
        pos = np.array(self.scene.point_light_pos, dtype=np.float32)  # in whatever frame the tracer keeps
        pos[:, 1] -= drop
        self.scene.point_light_pos = pos
        self.point_light_drop = drop

    def render(self, camera: Camera, spp: int = 1, seed: int | None = 0) -> Render:
        if self.noise_free:
            seed = None
        res = self.tracer.render(self.scene, camera, spp=spp, seed=seed, integrator=self.integrator,
                                 max_depth=self.max_depth, **self.render_options)
        out = _from_tracer_result(res, spp, self.name, noise_free=self.noise_free)
        out.aovs.update(self.aovs(camera))
        return out

    def light_points(self, max_points: int = 16) -> np.ndarray:
        """Points (world space) whose visibility defines shadow edges: the point lights (as this source
        placed them), and the corners and centroids of the emissive triangles; float64 ``(n, 3)``."""
        sc = self.scene
        pts = [np.array([p.position for p in getattr(sc, "point_lights", [])], dtype=np.float64).reshape(-1, 3)]
        pts[0][:, 1] -= self.point_light_drop
        lt = np.asarray(getattr(sc, "light_triangles", np.zeros(0, int)))
        if len(lt):
            tri = np.asarray(sc.vertices, dtype=np.float64)[np.asarray(sc.triangles)[lt]]  # (n, 3, 3)
            pts.append(tri.mean(axis=1))
            pts.append(np.unique(tri.reshape(-1, 3), axis=0))
        return np.concatenate(pts, axis=0)[:max_points]

    def _accel_frame(self) -> np.ndarray:
        """The offset to subtract from world points before querying the scene's accelerator."""
        accel = self.scene.accel
        if np.any(np.asarray(getattr(accel, "shift", np.zeros(3)))):
            return np.zeros(3)  # the accelerator takes world points and shifts them itself
        return np.asarray(getattr(self.scene, "shift", np.zeros(3)), dtype=np.float64)

    def aovs(self, camera: Camera) -> dict[str, np.ndarray]:
        """Geometric AOVs of each pixel-centre ray, cast with the scene's own accelerator (not timed).

        ``depth`` (inf for a miss), ``normal`` (geometric), and ``prim_id``: an object label combining
        the material id with the visibility bits of the :meth:`light_points` from the hit point, so
        that a neighbour on another object or on the other side of a shadow boundary (of a point light,
        or of any corner of an area light: the edges of the penumbra) differs. The two triangles of a
        quad share a label, so their diagonal is not an edge.
        """
        sc = self.scene
        w, h = camera.size
        shift = self._accel_frame()
        centres = camera.pixel_grid(None, 1, None)[:, :, 0]
        origins, dirs, valid = camera.pixel_to_world(centres)
        o, d, ok = origins.reshape(-1, 3), dirs.reshape(-1, 3), valid.reshape(-1)
        prim = np.full(len(ok), -1, dtype=np.int64)
        dist = np.full(len(ok), np.inf)
        k = np.nonzero(ok)[0]
        if len(k):
            p, t = sc.accel.intersect(o[k] - shift, d[k])
            prim[k], dist[k] = p, t
        normals = np.asarray(sc.normals, dtype=np.float64)
        hit = prim >= 0
        n = np.where(hit[:, None], normals[np.maximum(prim, 0)], 0.0)
        label = np.full(len(ok), -1, dtype=np.int64)
        hk = np.nonzero(hit)[0]
        if len(hk):
            mats = np.asarray(sc.material_ids, dtype=np.int64)[prim[hk]]
            pos = o[hk] + dist[hk, None] * d[hk]
            nf = n[hk] * np.where(np.einsum("ij,ij->i", n[hk], d[hk]) > 0, -1.0, 1.0)[:, None]
            start = pos + float(getattr(sc, "epsilon", 1e-4)) * nf
            bits = np.zeros(len(hk), dtype=np.int64)
            for i, lp in enumerate(self.light_points()):
                to = lp[None, :] - start
                facing = np.einsum("ij,ij->i", to, nf) > 0
                blocked = sc.accel.occluded(start - shift, to, tmax=0.999)
                bits |= (facing & ~blocked).astype(np.int64) << i
            label[hk] = mats * (1 << 16) + bits
        return {"depth": dist.reshape(h, w), "normal": n.reshape(h, w, 3), "prim_id": label.reshape(h, w)}


def _get(res, name, default=None):
    if isinstance(res, dict):
        return res.get(name, default)
    return getattr(res, name, default)


def _from_tracer_result(res, spp: int, name: str, noise_free: bool) -> Render:
    """A :class:`Render` from a ``tracer.RenderResult``; its ``variance`` is that of each pixel's mean."""
    image = np.asarray(_get(res, "image"), dtype=np.float32)
    if image.ndim == 3 and image.shape[-1] == 4:
        alpha = image[..., 3]
        image = image[..., :3]
    else:
        alpha = _get(res, "alpha")
        alpha = np.ones(image.shape[:2], np.float32) if alpha is None else np.asarray(alpha, np.float32)
        if alpha.ndim == 3:
            alpha = alpha[..., 0]
    variance = _get(res, "variance")
    stderr = None
    if noise_free:
        stderr = np.zeros_like(image)
    elif variance is not None:
        var = np.asarray(variance, dtype=np.float64)
        if var.ndim == 2:
            var = var[..., None]
        var = np.broadcast_to(var, image.shape)
        covered = alpha > 0
        if np.all(np.isfinite(var[covered])):  # inf where a pixel has fewer than two samples: unknown
            stderr = np.sqrt(np.where(np.isfinite(var), var, 0.0)).astype(np.float32)
    seconds = float(_get(res, "seconds", 0.0))
    return Render(image, alpha, stderr, {}, seconds, int(_get(res, "spp", spp)), {"source": name})


NOISE_FREE_CORNELL_DROP = 0.14  # metres: the point light 15 cm under the ceiling instead of 1 cm


def make_source(scene: str, integrator: str | None = None, max_depth: int = 8, noise_free: bool = False):
    """``analytic`` gives :class:`AnalyticSource`; any other name a tracer scene.

    In noise-free mode the Cornell box becomes ``cornell-point`` with its point light lowered (see
    :meth:`TracerSource._lower_point_lights`) rendered by the ``direct`` integrator at fixed sample
    positions: deterministic, so only resampling error remains.
    """
    if scene in ("analytic", "analytic-sky"):
        return AnalyticSource()
    drop = 0.0
    if noise_free and scene in ("cornell", "cornell-point"):
        scene, drop = "cornell-point", NOISE_FREE_CORNELL_DROP
    integrator = integrator or ("direct" if noise_free else "path")
    return TracerSource(scene, integrator=integrator, max_depth=max_depth, noise_free=noise_free,
                        point_light_drop=drop)
