"""Built-in scenes.

- ``cornell``: the Cornell box from the measurements published by the Cornell Program of Computer
  Graphics (http://www.graphics.cornell.edu/online/box/data.html), in metres. The published frame is
  right-handed (red wall at x = 0.55, seen on the left from the camera at z = -0.8); lenslab's camera
  frame has +x to the right of +z forward with +y up, so x is mirrored (``x -> 0.556 - x``) to keep the
  red wall on the left as in the photographs. Albedos and the light's radiance are the usual RGB
  reductions of the published spectra (as in Bitterli's and Mitsuba's versions): white
  (0.725, 0.71, 0.68), red (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091), light (17, 12, 4).
  Views: ``default`` is the published camera's line of sight (x = 278 mm, y = 273 mm, looking along
  +z into the box, +y up) with the eye in the box's opening (1 mm inside the front plane), so that any
  lens, a 180-degree fisheye included, sees the box and nothing but the box; its own lens is a
  90-degree perspective, which shows the whole back wall. ``published`` is the published camera
  itself: the eye 800 mm in front of the opening, 35 mm focal length on 25 mm film (a 39.3 degree
  field of view), the framing of the photographs.
- ``cornell-point``: the same box lit by a point light just under the ceiling instead of the area
  light: with ``integrator="direct"`` and ``seed=None`` its renders are free of noise.
- ``sky``: a mirror sphere, a glossy (Phong) sphere and a diffuse box on a ground plane, under an open
  sky: a constant colour, or an HDR equirect panorama given as ``env=path``.
- ``furnace``: a closed sphere seen from inside, emitting ``emission`` from its inner face with
  albedo ``albedo``: every pixel converges to ``emission / (1 - albedo)``.
- ``plane``: a diffuse square under a uniform sky (``sky`` radiance, ``albedo``): radiance ``albedo * sky``.
- ``arealight``: a small square emitter of side ``size`` at ``height`` over a large diffuse plane.
"""

from __future__ import annotations

import numpy as np

from tracer.materials import Material
from tracer.scene import PointLight, Scene, View, merge_meshes, polydata_triangles

MM = 1e-3
MIRROR_X = 556.0  # x -> 556 - x (millimetres), see the module docstring

WHITE = Material("white", kd=(0.725, 0.71, 0.68))
RED = Material("red", kd=(0.63, 0.065, 0.05))
GREEN = Material("green", kd=(0.14, 0.45, 0.091))
LIGHT = Material("light", kd=(0.78, 0.78, 0.78), emission=(17.0, 12.0, 4.0))

# Published data, millimetres, right-handed frame.
FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
LIGHT_QUAD = [(343.0, 548.7, 227.0), (343.0, 548.7, 332.0), (213.0, 548.7, 332.0), (213.0, 548.7, 227.0)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
RIGHT_GREEN = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]
LEFT_RED = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]
SHORT_BLOCK = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
]
TALL_BLOCK = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
]
CAMERA_EYE = (278.0, 273.0, -800.0)  # published, millimetres
OPENING_EYE = (278.0, 273.0, 1.0)  # the same line of sight, 1 mm inside the opening (z = 0)
CAMERA_FOV = float(np.degrees(2 * np.arctan(12.5 / 35.0)))  # 25 mm film, 35 mm lens


def _cornell_points(quad) -> np.ndarray:
    p = np.asarray(quad, dtype=np.float64)
    p[:, 0] = MIRROR_X - p[:, 0]
    return p * MM


def quad(points, facing=None) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and two triangles of a planar quad; with ``facing``, triangles are wound so their
    normal points along it."""
    p = np.asarray(points, dtype=np.float64)
    t = np.array([[0, 1, 2], [0, 2, 3]])
    if facing is not None:
        n = np.cross(p[1] - p[0], p[2] - p[0])
        if np.dot(n, facing) < 0:
            t = t[:, ::-1]
    return p, t


def cornell(light: str = "area") -> Scene:
    """The Cornell box (see the module docstring); ``light`` is ``area`` or ``point``."""
    parts = [quad(_cornell_points(q)) + (m,) for q, m in
             ((FLOOR, WHITE), (CEILING, WHITE), (BACK, WHITE), (RIGHT_GREEN, GREEN), (LEFT_RED, RED))]
    for block in (SHORT_BLOCK, TALL_BLOCK):
        parts += [quad(_cornell_points(q)) + (WHITE,) for q in block]
    lp = _cornell_points(LIGHT_QUAD)
    points = []
    if light == "area":
        parts.append(quad(lp, facing=(0, -1, 0)) + (LIGHT,))
    elif light == "point":
        area = float(np.linalg.norm(np.cross(lp[1] - lp[0], lp[3] - lp[0])))
        centre = lp.mean(axis=0) - np.array([0.0, 0.01, 0.0])
        # the on-axis intensity of the area light it replaces: radiance x area
        points.append(PointLight(centre, tuple(np.asarray(LIGHT.emission) * area)))
    else:
        raise ValueError(f"cornell: light must be 'area' or 'point', got {light!r}")
    eye, inside = _cornell_points([CAMERA_EYE, OPENING_EYE])
    published = View(eye=tuple(eye), look_at=tuple(eye + [0, 0, 1]), lens=f"perspective:fov={CAMERA_FOV:.4f}")
    default = View(eye=tuple(inside), look_at=tuple(inside + [0, 0, 1]), lens="perspective:fov=90")
    name = "cornell" if light == "area" else "cornell-point"
    return merge_meshes(parts, point_lights=points, views={"default": default, "published": published}, name=name)


def sphere_mesh(center, radius, resolution=48, inward=False):
    import pyvista as pv

    v, t = polydata_triangles(pv.Sphere(radius=radius, center=center, theta_resolution=resolution,
                                        phi_resolution=resolution))
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    outward = np.einsum("ij,ij->i", n, v[t].mean(axis=1) - np.asarray(center)) > 0
    want = ~outward if inward else outward
    t = np.where(want[:, None], t, t[:, ::-1])
    return v, t


def box_mesh(center, size):
    import pyvista as pv

    c, s = np.asarray(center, float), np.asarray(size, float)
    return polydata_triangles(pv.Box(bounds=(c[0] - s[0] / 2, c[0] + s[0] / 2, c[1] - s[1] / 2, c[1] + s[1] / 2,
                                             c[2] - s[2] / 2, c[2] + s[2] / 2)))


def sky(env: str | None = None, radiance=(0.8, 0.9, 1.1), yaw: float = 0.0) -> Scene:
    """Mirror and glossy spheres and a diffuse box on a ground plane, under an open sky."""
    from tracer.envlight import ConstantEnvironment, EquirectEnvironment

    ground = Material("ground", kd=(0.5, 0.5, 0.5))
    mirror = Material("mirror", kind="mirror", kd=0.0, ks=(0.95, 0.95, 0.95))
    glossy = Material("glossy", kind="glossy", kd=(0.45, 0.08, 0.05), ks=(0.4, 0.4, 0.4), exponent=80.0)
    box = Material("box", kd=(0.2, 0.35, 0.7))
    parts = [
        quad([(-10, 0, -10), (10, 0, -10), (10, 0, 10), (-10, 0, 10)]) + (ground,),
        sphere_mesh((-0.6, 0.5, 0.0), 0.5) + (mirror,),
        sphere_mesh((0.6, 0.4, -0.3), 0.4) + (glossy,),
        box_mesh((0.0, 0.2, 0.9), (0.6, 0.4, 0.6)) + (box,),
    ]
    environment = EquirectEnvironment.from_file(env, yaw=yaw) if env else ConstantEnvironment(radiance)
    view = View(eye=(0.0, 1.2, -3.2), look_at=(0.0, 0.4, 0.0), lens="perspective:fov=60")
    return merge_meshes(parts, environment=environment, views={"default": view}, name="sky")


def furnace(emission: float = 1.0, albedo: float = 0.5, resolution: int = 16) -> Scene:
    """A closed sphere of radius 1 around the origin, emitting and reflecting on its inner face."""
    mat = Material("furnace", kd=albedo, emission=emission)
    view = View(eye=(0.0, 0.0, 0.0), look_at=(0.0, 0.0, 1.0), lens="perspective:fov=90")
    return merge_meshes([sphere_mesh((0, 0, 0), 1.0, resolution, inward=True) + (mat,)],
                        views={"default": view}, name="furnace")


def plane(albedo: float = 0.5, radiance: float = 1.0) -> Scene:
    """A diffuse square (side 2, at y = 0, facing +y) under a uniform sky."""
    from tracer.envlight import ConstantEnvironment

    mat = Material("plane", kd=albedo)
    view = View(eye=(0.0, 1.0, 0.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0), lens="perspective:fov=40")
    return merge_meshes([quad([(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)], facing=(0, 1, 0)) + (mat,)],
                        environment=ConstantEnvironment(radiance), views={"default": view}, name="plane")


def arealight(size: float = 0.2, height: float = 1.0, radiance: float = 10.0, albedo: float = 0.5) -> Scene:
    """A square emitter (side ``size``, facing down) centred ``height`` above a large diffuse floor."""
    h, s = float(height), float(size) / 2
    floor = Material("floor", kd=albedo)
    light = Material("light", kd=0.0, emission=radiance)
    view = View(eye=(0.0, h / 2, 0.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0), lens="perspective:fov=2")
    parts = [quad([(-50, 0, -50), (50, 0, -50), (50, 0, 50), (-50, 0, 50)], facing=(0, 1, 0)) + (floor,),
             quad([(-s, h, -s), (s, h, -s), (s, h, s), (-s, h, s)], facing=(0, -1, 0)) + (light,)]
    return merge_meshes(parts, views={"default": view}, name="arealight")


BUILTINS = {
    "cornell": lambda **kw: cornell("area", **kw),
    "cornell-point": lambda **kw: cornell("point", **kw),
    "sky": sky,
    "furnace": furnace,
    "plane": plane,
    "arealight": arealight,
}
