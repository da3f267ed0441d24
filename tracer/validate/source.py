"""Validation sources that the ray tracer renders: a ``tracer`` scene as a :mod:`lenslab.validate` source.

:class:`TracerSource` renders a scene of this package through any lenslab camera and returns a
:class:`lenslab.validate.sources.Render`; :func:`make_source` chooses between it and the noise-free
:class:`lenslab.validate.sources.AnalyticSource`.
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses import Camera
from lenslab.validate.sources import AnalyticSource, Render


# -- the ray tracer ----------------------------------------------------------------------------------
class TracerSource:
    """A scene of the ``tracer`` package rendered with one of its integrators."""

    noise_free = False
    shadow_edges = False  # shadow edges come from the light-visibility bits of the prim_id AOV

    def __init__(self, scene: str = "cornell", integrator: str = "path", max_depth: int = 8,
                 noise_free: bool = False, point_light_drop: float = 0.0, **render_options):
        import tracer

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
        lower_point_lights(self.scene, drop)
        self.point_light_drop = drop

    def render(self, camera: Camera, spp: int = 1, seed: int | None = 0) -> Render:
        if self.noise_free:
            seed = None
        if getattr(self, "client", None) is not None:  # tiles on a Dask cluster: the same pixels as here
            from tracer.tiles import render_tiled

            res = render_tiled(self.client, self.scene_name, camera, spp=spp, seed=seed, integrator=self.integrator,
                               max_depth=self.max_depth,
                               prepare=(lower_point_lights, (self.point_light_drop,)) if self.point_light_drop else None)
        else:
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


def lower_point_lights(scene, drop: float) -> None:
    """Move the scene's point lights down by ``drop`` scene units (see :meth:`TracerSource._lower_point_lights`)."""
    pos = np.array(scene.point_light_pos, dtype=np.float32)  # in whatever frame the tracer keeps
    pos[:, 1] -= drop
    scene.point_light_pos = pos


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
