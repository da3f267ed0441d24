"""A scene: triangles with one material per triangle, lights, an environment, and suggested views.

Triangles are the only geometry. Emissive triangles are the area lights, chosen for next-event
estimation in proportion to their power (area x mean radiance) and sampled uniformly on their area.
Point lights (position, intensity in W/sr per channel) exist for noise-free reference renders.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from lenslab.errors import LenslabError
from tracer.materials import Material, MaterialTable
from tracer.sampling import F32, Distribution1D


class SceneError(LenslabError, ValueError):
    """A scene cannot be built or loaded as given."""


@dataclass
class PointLight:
    position: tuple
    intensity: tuple  # radiant intensity per channel (radiance x area for a tiny emitter), W/sr

    def __post_init__(self):
        self.position = tuple(float(v) for v in np.broadcast_to(np.asarray(self.position, float), (3,)))
        self.intensity = tuple(float(v) for v in np.broadcast_to(np.asarray(self.intensity, float), (3,)))


@dataclass
class View:
    """A suggested camera pose: eye, target point, up vector, and the lens spec it was designed for."""

    eye: tuple = (0.0, 0.0, 0.0)
    look_at: tuple = (0.0, 0.0, 1.0)
    up: tuple = (0.0, 1.0, 0.0)
    lens: str = "perspective:fov=60"


@dataclass
class Scene:
    """Triangle geometry, per-triangle material ids and the material table, lights and environment.

    ``vertices`` (V, 3) float, ``triangles`` (T, 3) int, ``material_ids`` (T,) int indexing
    ``materials``. Degenerate triangles (zero area) are dropped and counted in ``dropped``.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    material_ids: np.ndarray
    materials: list
    environment: object = None
    point_lights: list = field(default_factory=list)
    views: dict = field(default_factory=dict)
    name: str = "scene"
    dropped: int = 0

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        t = np.asarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        m = np.asarray(self.material_ids, dtype=np.int64).reshape(-1)
        if len(m) != len(t):
            raise SceneError(f"{len(t)} triangles but {len(m)} material ids; give one material id per triangle")
        if not self.materials:
            self.materials = [Material()]
        if t.size and (t.min() < 0 or t.max() >= len(v)):
            raise SceneError("a triangle refers to a vertex that does not exist; check the face indices")
        if m.size and (m.min() < 0 or m.max() >= len(self.materials)):
            raise SceneError("a triangle refers to a material that does not exist; check the material ids")
        if not np.all(np.isfinite(v)):
            raise SceneError("vertex coordinates must be finite")
        p0, p1, p2 = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
        cross = np.cross(p1 - p0, p2 - p0)
        area2 = np.linalg.norm(cross, axis=1)
        diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) if len(v) else 1.0
        keep = area2 > 1e-14 * max(diag, 1e-30) ** 2  # twice the area, relative to the scene size
        self.dropped += int((~keep).sum())
        t, m, cross, area2 = t[keep], m[keep], cross[keep], area2[keep]
        if len(t) == 0 and self.environment is None and not self.point_lights:
            raise SceneError("the scene has no triangles, no environment and no lights: nothing to render")
        self.vertices, self.triangles, self.material_ids = v, t.astype(np.int32), m.astype(np.int32)
        self.table = MaterialTable(list(self.materials))
        # the integrator works in float32 relative to the centre of the geometry, where float32 is
        # most precise: ``local = world - shift``
        self.shift = 0.5 * (v[t].reshape(-1, 3).min(axis=0) + v[t].reshape(-1, 3).max(axis=0)) if len(t) else np.zeros(3)
        self.v0 = (v[t[:, 0]] - self.shift).astype(F32) if len(t) else np.zeros((0, 3), F32)
        self.e1 = (v[t[:, 1]] - v[t[:, 0]]).astype(F32) if len(t) else np.zeros((0, 3), F32)
        self.e2 = (v[t[:, 2]] - v[t[:, 0]]).astype(F32) if len(t) else np.zeros((0, 3), F32)
        self.normals = (cross / np.where(area2 > 0, area2, 1)[:, None]).astype(F32)
        self.areas = 0.5 * area2
        self.diagonal = max(diag, 1e-6)
        # offset of secondary ray origins off their surface: about a hundred float32 rounding steps of
        # the largest coordinates (renders show no self-shadowing down to 1e-6 of the diagonal)
        self.epsilon = float(1e-5 * self.diagonal)
        self._setup_lights()
        self._accel = None

    # -- lights ----------------------------------------------------------------------------
    def _setup_lights(self) -> None:
        em = self.table.emission[self.material_ids] if len(self.material_ids) else np.zeros((0, 3), F32)
        radiance = em.mean(axis=1) if len(em) else np.zeros(0)
        self.emissive = radiance > 0
        self.light_triangles = np.nonzero(self.emissive)[0].astype(np.int64)
        sides = np.where(self.table.two_sided[self.material_ids[self.light_triangles]], 2.0, 1.0)
        power = self.areas[self.light_triangles] * radiance[self.light_triangles] * sides
        self.light_power = float(np.pi * power.sum())
        self.light_dist = Distribution1D(power) if len(power) else None
        # area-measure density of choosing a point on each triangle (0 for non-emitters)
        self.light_area_pdf = np.zeros(len(self.triangles), dtype=F32)
        if self.light_dist is not None:
            self.light_area_pdf[self.light_triangles] = (self.light_dist.pmf / self.areas[self.light_triangles]).astype(F32)
        self.point_light_pos = (np.array([p.position for p in self.point_lights], dtype=np.float64).reshape(-1, 3)
                                - self.shift).astype(F32)
        self.point_light_int = np.array([p.intensity for p in self.point_lights], dtype=F32).reshape(-1, 3)

    @property
    def has_area_lights(self) -> bool:
        return len(self.light_triangles) > 0

    # -- geometry --------------------------------------------------------------------------
    @property
    def accel(self):
        """The embree accelerator (in the scene's local frame, ``world - shift``), built on first use and
        kept for the life of the scene."""
        if self._accel is None:
            from tracer.accel import Accelerator

            self._accel = Accelerator(self.vertices - self.shift, self.triangles, centre=False)
        return self._accel

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        used = self.vertices[np.unique(self.triangles)] if len(self.triangles) else np.zeros((1, 3))
        return used.min(axis=0), used.max(axis=0)

    def camera(self, lens: str | None = None, size=(512, 512), view: str | None = None, **pose):
        """A :class:`~lenslab.lenses.Camera` with ``lens`` (default: the view's own) at a named view.

        ``pose`` keywords (``yaw``, ``pitch``, ``roll``, ``eye``, ``look_at``, ``up``) override the view;
        a new ``eye`` alone keeps the view's viewing direction.
        """
        from lenslab.lenses import Camera

        v = self.view(view)
        if any(k in pose for k in ("yaw", "pitch", "roll")) and "look_at" not in pose:
            return Camera.from_spec(lens or v.lens, size, yaw=pose.get("yaw", 0.0), pitch=pose.get("pitch", 0.0),
                                    roll=pose.get("roll", 0.0), eye=pose.get("eye", v.eye))
        eye = pose.get("eye", v.eye)
        # a new eye alone keeps the view's direction (not its target point)
        at = pose["look_at"] if "look_at" in pose else np.asarray(eye, float) + np.subtract(v.look_at, v.eye)
        return Camera.from_spec(lens or v.lens, size, eye=eye, look_at=at, up=pose.get("up", v.up))

    def view(self, name: str | None = None) -> View:
        """The view ``name``, else the default one (the first, or one that frames the geometry when none is named)."""
        return self.views.get(name or "default") or (next(iter(self.views.values())) if self.views else
                                                     self.framing_view())

    def framing_view(self, fov: float = 60.0) -> View:
        """A view from -z that frames the whole geometry (for scenes that name no camera)."""
        if not len(self.triangles):
            return View(lens=f"perspective:fov={fov:g}")
        lo, hi = self.bounds
        centre = 0.5 * (lo + hi)
        radius = 0.5 * float(np.linalg.norm(hi - lo))
        distance = radius / np.sin(np.radians(fov) / 2) if radius > 0 else 1.0
        eye = centre - np.array([0.0, 0.0, distance])
        return View(eye=tuple(eye), look_at=tuple(centre), lens=f"perspective:fov={fov:g}")

    def summary(self) -> str:
        kinds = sorted({m.kind for m in self.materials})
        env = type(self.environment).__name__ if self.environment is not None else "none"
        return (f"{self.name}: {len(self.triangles)} triangles ({self.dropped} degenerate dropped), "
                f"{len(self.materials)} materials ({', '.join(kinds)}), {len(self.light_triangles)} emissive "
                f"triangles, {len(self.point_lights)} point lights, environment {env}")


def merge_meshes(parts, **scene_kwargs) -> Scene:
    """Build a scene from ``(vertices, triangles, Material)`` parts; identical materials are shared by name."""
    verts, tris, mids, materials, index = [], [], [], [], {}
    offset = 0
    for v, t, mat in parts:
        v = np.asarray(v, dtype=np.float64).reshape(-1, 3)
        t = np.asarray(t, dtype=np.int64).reshape(-1, 3)
        key = mat.name
        if key not in index or materials[index[key]] != mat:
            if key in index:
                key = f"{mat.name}#{len(materials)}"
            index[key] = len(materials)
            materials.append(mat)
        verts.append(v)
        tris.append(t + offset)
        mids.append(np.full(len(t), index[key]))
        offset += len(v)
    return Scene(np.concatenate(verts) if verts else np.zeros((0, 3)),
                 np.concatenate(tris) if tris else np.zeros((0, 3), int),
                 np.concatenate(mids) if mids else np.zeros(0, int), materials, **scene_kwargs)


def polydata_triangles(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of a pyvista mesh (polygons triangulated)."""
    mesh = mesh.extract_surface() if not hasattr(mesh, "faces") else mesh
    tri = mesh.triangulate()
    faces = np.asarray(tri.faces).reshape(-1, 4)
    if len(faces) and not np.all(faces[:, 0] == 3):
        raise SceneError("the mesh still has non-triangle faces after triangulation")
    return np.asarray(tri.points, dtype=np.float64), faces[:, 1:].astype(np.int64)
