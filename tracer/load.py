"""Loading scenes: built-in names, OBJ with MTL, PLY/STL (pyvista), and TOML scene files.

OBJ: ``v`` and ``f`` (polygons are fan-triangulated; negative indices count back), ``usemtl`` and
``mtllib``. MTL: ``Kd`` diffuse albedo, ``Ks``/``Ns`` a Phong lobe (``illum 3``, or ``Ks`` with a
zero ``Kd``, makes a perfect mirror of reflectance ``Ks``), ``Ke`` emission, and ``Ka`` as emission
when the scene asks for it (``ambient_as_emission``, as some course files light their scenes).

Handedness: lenslab's (and pbrt's) world and camera frames are left-handed (+x right, +y up, +z
forward). Mesh files (OBJ, PLY, STL, VTK) come from right-handed tools (Blender, Maya, Mitsuba 3, most
exporters), so by default they are mirrored on import, ``x -> -x`` with each triangle's winding
reversed: the scene then renders as the tool shows it, a point ``(x, y, z)`` of the tool standing at
``(-x, y, z)`` in lenslab (give ``--eye``/``--look-at`` there). ``handedness="left"`` (``tracer render
--handedness left``, or ``handedness = "left"`` on a TOML ``[[mesh]]``) keeps a left-handed asset as it
is. TOML scene coordinates (shapes, lights, cameras, translations) are lenslab's own.

A bare mesh file without emitters is lit by a uniform white sky (radiance 1) and seen from a camera
that frames it. A TOML scene names meshes, materials, lights, an environment and cameras::

    [scene]
    name = "demo"

    [materials.white]
    kd = [0.7, 0.7, 0.7]                 # kind = "diffuse" | "glossy" | "mirror"; ks, exponent, emission

    [[mesh]]
    file = "bunny.ply"                    # relative to this file; OBJ keeps its MTL unless material is set
    handedness = "right"                  # the file's frame: "right" (default, mirrored x -> -x) or "left"
    material = "white"
    scale = 1.0
    translate = [0.0, 0.0, 0.0]

    [[mesh]]
    shape = "sphere"                      # or "quad" (points = 4 corners), "box" (center, size)
    center = [0.0, 1.0, 0.0]
    radius = 0.5
    material = "white"

    [[point_light]]
    position = [0.0, 2.0, 0.0]
    intensity = [5.0, 5.0, 5.0]

    [environment]
    radiance = [0.5, 0.6, 0.8]            # or image = "sky.exr", yaw = 0.0, scale = 1.0

    [cameras.default]
    lens = "perspective:fov=60"
    eye = [0.0, 1.0, -3.0]
    look_at = [0.0, 0.5, 0.0]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tracer.materials import KINDS, Material
from tracer.scene import PointLight, Scene, SceneError, View, merge_meshes, polydata_triangles

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".vtk", ".vtp")


def check_scene_name(name: str) -> None:
    """:class:`SceneError` when ``name`` is neither a built-in scene nor named as a scene file is (a name
    alone settles it: the command line reports it as a usage error before anything is read)."""
    from tracer.builtin import BUILTINS

    if name not in BUILTINS and Path(name).suffix.lower() not in MESH_SUFFIXES + (".toml",):
        raise SceneError(f"{name!r} is neither a built-in scene ({', '.join(BUILTINS)}) nor a scene file "
                         f"({', '.join(MESH_SUFFIXES + ('.toml',))})")


def check_scene_argument(name: str) -> None:
    """:func:`check_scene_name` for a command's ``--scene``: a usage error (exit 2) before anything is read."""
    from lenslab.errors import UsageError

    try:
        check_scene_name(name)
    except SceneError as exc:
        raise UsageError(str(exc)) from None


def load_scene(source, **kwargs) -> Scene:
    """A scene from a built-in name (``cornell``, ``cornell-point``, ``sky``, ...) or a file path.

    Keyword arguments go to the built-in scene's builder (e.g. ``env=`` for ``sky``) or to the
    file loader (``material=`` for PLY/STL, ``ambient_as_emission=`` for OBJ).
    """
    if isinstance(source, Scene):
        return source
    from tracer.builtin import BUILTINS

    name = str(source)
    if name in BUILTINS:
        return BUILTINS[name](**kwargs)
    check_scene_name(name)
    path = Path(name)
    suffix = path.suffix.lower()
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such scene file")
    if suffix == ".toml":
        return load_toml(path, **kwargs)
    parts, dropped = load_mesh(path, **kwargs)
    scene = merge_meshes(parts, name=path.stem, dropped=dropped)
    if not scene.has_area_lights:
        from tracer.envlight import ConstantEnvironment

        scene.environment = ConstantEnvironment(1.0)  # a bare mesh is shown under a uniform white sky
    return scene


# -- OBJ / MTL -------------------------------------------------------------------------------
def _floats(tokens, n, where):
    try:
        vals = [float(x) for x in tokens[:n]]
    except ValueError:
        raise SceneError(f"{where}: expected {n} numbers, got {' '.join(tokens)!r}") from None
    if len(vals) == 1 and n == 3:
        vals = vals * 3
    if len(vals) != n:
        raise SceneError(f"{where}: expected {n} numbers, got {' '.join(tokens)!r}")
    return vals


def _statements(path: Path):
    """``(where, keyword, arguments)`` for each non-empty line of an OBJ or MTL file, comments removed."""
    from lenslab.inputs.sidefile import read_side_bytes

    text = read_side_bytes(path, "mesh file" if path.suffix.lower() == ".obj" else "material file").decode(
        "utf-8", "replace")
    for lineno, line in enumerate(text.splitlines(), 1):
        tokens = line.split("#", 1)[0].split()
        if tokens:
            yield f"{path}:{lineno}", tokens[0], tokens[1:]


def read_mtl(path: Path, ambient_as_emission: bool = False) -> dict[str, Material]:
    """Materials of an MTL file by name."""
    if not path.is_file():
        raise SceneError(f"{path}: the material library named by the OBJ file does not exist")
    raw: dict[str, dict] = {}
    current = None
    for where, key, args in _statements(path):
        if key == "newmtl":
            if not args:
                raise SceneError(f"{where}: newmtl without a name")
            current = raw.setdefault(" ".join(args), {})
        elif current is None:
            continue
        elif key in ("Kd", "Ks", "Ke", "Ka"):
            current[key] = _floats(args, 3, where)
        elif key == "Ns":
            current["Ns"] = _floats(args, 1, where)[0]
        elif key == "illum":
            current["illum"] = int(_floats(args, 1, where)[0])
    out = {}
    for name, m in raw.items():
        kd = np.array(m.get("Kd", (0.8, 0.8, 0.8)))
        ks = np.array(m.get("Ks", (0.0, 0.0, 0.0)))
        emission = np.array(m.get("Ke", (0.0, 0.0, 0.0)))
        if ambient_as_emission and "Ka" in m:
            emission = np.maximum(emission, np.array(m["Ka"]))
        exponent = float(m.get("Ns", 50.0))
        if m.get("illum") == 3 or (ks.max() > 0 and kd.max() == 0 and exponent >= 1000):
            out[name] = Material(name, kind="mirror", kd=0.0, ks=ks if ks.max() > 0 else 1.0, emission=emission)
        elif ks.max() > 0:
            total = (kd + ks).max()
            if total > 1:  # keep energy: scale both lobes down together
                kd, ks = kd / total, ks / total
            out[name] = Material(name, kind="glossy", kd=kd, ks=ks, exponent=exponent, emission=emission)
        else:
            out[name] = Material(name, kd=np.clip(kd, 0, 1), emission=emission)
    return out


def read_obj(path: Path, ambient_as_emission: bool = False, material: Material | None = None):
    """``[(vertices, triangles, Material), ...]`` (one part per material) and the count of dropped faces."""
    verts: list = []
    faces: dict[str, list] = {}
    library: dict[str, Material] = {}
    current = "default"
    dropped = 0
    for where, key, args in _statements(path):
        if key == "v":
            if len(args) < 3:
                raise SceneError(f"{where}: a vertex needs x y z, got {' '.join(args)!r}")
            verts.append(_floats(args, 3, where))
        elif key == "f":
            idx = []
            for a in args:
                try:
                    i = int(a.split("/")[0])
                except ValueError:
                    raise SceneError(f"{where}: bad face vertex {a!r}") from None
                i = i - 1 if i > 0 else len(verts) + i
                if not 0 <= i < len(verts):
                    raise SceneError(f"{where}: face refers to vertex {a} but only {len(verts)} are defined so far")
                idx.append(i)
            if len(idx) < 3:
                dropped += 1
                continue
            tri = [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]  # fan triangulation
            faces.setdefault(current, []).extend(tri)
        elif key == "usemtl":
            current = " ".join(args) or "default"
        elif key == "mtllib":
            for name in (" ".join(args),) if (path.parent / " ".join(args)).is_file() else args:
                library.update(read_mtl(path.parent / name, ambient_as_emission))
    parts = []
    v = np.asarray(verts, dtype=np.float64).reshape(-1, 3)
    for name, tris in faces.items():
        if material is not None:
            mat = material
        elif name in library:
            mat = library[name]
        elif name == "default":
            mat = Material()
        else:
            raise SceneError(
                f"{path}: usemtl {name!r} names a material that no mtllib defines"
                + (f" (defined: {', '.join(sorted(library))})" if library else " (no material library was loaded)")
            )
        parts.append((v, np.asarray(tris, dtype=np.int64), mat))
    if not parts:
        raise SceneError(f"{path}: no faces found")
    return parts, dropped


#: the frames a mesh file's coordinates may be in: "right" (Blender, Maya, Mitsuba 3, most exporters:
#: mirrored on import) or "left" (lenslab's and pbrt's own frame: kept as they are)
HANDEDNESS = ("right", "left")


def mirror_to_left_handed(vertices: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A right-handed tool's mesh in lenslab's left-handed frame: ``x -> -x``, and each triangle's winding
    reversed so that its front face (and normal) is the mirror image of the tool's."""
    v = np.array(vertices, dtype=np.float64, copy=True)
    v[:, 0] = -v[:, 0]
    return v, np.ascontiguousarray(np.asarray(triangles)[:, [0, 2, 1]])


def check_handedness(handedness: str) -> str:
    key = str(handedness).strip().lower()
    if key not in HANDEDNESS:
        raise SceneError(f"handedness must be one of {', '.join(HANDEDNESS)}, not {handedness!r}")
    return key


def load_mesh(path: Path, material: Material | None = None, ambient_as_emission: bool = False, scale=1.0,
              translate=(0.0, 0.0, 0.0), handedness: str = "right"):
    """Mesh parts of one file: OBJ through :func:`read_obj`, other formats through pyvista.

    ``handedness="right"`` (the default): the file comes from a right-handed tool and is mirrored
    (:func:`mirror_to_left_handed`) so that it renders as that tool shows it; ``"left"`` keeps it.
    ``scale`` and ``translate`` apply afterwards, in lenslab's frame."""
    handedness = check_handedness(handedness)
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such mesh file")
    if path.suffix.lower() == ".obj":
        parts, dropped = read_obj(path, ambient_as_emission, material)
    else:
        import pyvista as pv

        from tracer.meshcheck import check_mesh_file

        check_mesh_file(path)
        try:
            mesh = pv.read(str(path))
        except Exception as exc:  # pyvista raises assorted types for unreadable files
            raise SceneError(f"{path}: cannot read the mesh ({exc})") from None
        v, t = polydata_triangles(mesh)
        parts, dropped = [(v, t, material or Material())], 0
    if handedness == "right":
        parts = [(*mirror_to_left_handed(v, t), m) for v, t, m in parts]
    out = [(v * scale + np.asarray(translate, dtype=np.float64), t, m) for v, t, m in parts]
    return out, dropped


# -- TOML scenes -----------------------------------------------------------------------------
def _material(name: str, spec: dict) -> Material:
    allowed = {"kind", "kd", "ks", "exponent", "emission", "two_sided"}
    unknown = set(spec) - allowed
    if unknown:
        raise SceneError(f"material {name!r}: unknown key(s) {', '.join(sorted(unknown))}; valid: {', '.join(sorted(allowed))}")
    if spec.get("kind", "diffuse") not in KINDS:
        raise SceneError(f"material {name!r}: kind must be one of {', '.join(KINDS)}")
    try:
        return Material(name, **spec)
    except (TypeError, ValueError) as exc:
        raise SceneError(str(exc)) from None


def _shape(spec: dict, where: str):
    from tracer import builtin

    kind = spec.get("shape")
    if kind == "sphere":
        return builtin.sphere_mesh(spec.get("center", (0, 0, 0)), float(spec.get("radius", 1.0)),
                               int(spec.get("resolution", 48)), bool(spec.get("inward", False)))
    if kind == "quad":
        return builtin.quad(spec["points"], spec.get("facing"))
    if kind == "box":
        return builtin.box_mesh(spec.get("center", (0, 0, 0)), spec.get("size", (1, 1, 1)))
    raise SceneError(f"{where}: unknown shape {kind!r}; use sphere, quad or box, or give file = ...")


def load_toml(path: Path, **_ignored) -> Scene:
    """A scene described by a TOML file (see the module docstring)."""
    from tracer.envlight import ConstantEnvironment, EquirectEnvironment

    from lenslab.inputs.safeload import load_toml
    from lenslab.inputs.sidefile import read_side_text

    doc = load_toml(read_side_text(path, "scene file", 16 << 20), path, SceneError)
    head = doc.get("scene", {})
    materials = {name: _material(name, spec) for name, spec in doc.get("materials", {}).items()}
    parts, dropped = [], 0
    for i, mesh in enumerate(doc.get("mesh", [])):
        where = f"{path}: mesh {i + 1}"
        mname = mesh.get("material")
        if mname is not None and mname not in materials:
            raise SceneError(f"{where}: unknown material {mname!r}; defined: {', '.join(sorted(materials)) or 'none'}")
        mat = materials.get(mname)
        if "file" in mesh:
            got, d = load_mesh(path.parent / mesh["file"], material=mat,
                               ambient_as_emission=bool(head.get("ambient_as_emission", False)),
                               scale=float(mesh.get("scale", 1.0)), translate=mesh.get("translate", (0, 0, 0)),
                               handedness=mesh.get("handedness", "right"))
            parts += got
            dropped += d
        else:
            v, t = _shape(mesh, where)
            parts.append((np.asarray(v) * float(mesh.get("scale", 1.0)) + np.asarray(mesh.get("translate", (0, 0, 0))),
                          t, mat or Material()))
    lights = [PointLight(pl["position"], pl["intensity"]) for pl in doc.get("point_light", [])]
    env = None
    if "environment" in doc:
        e = doc["environment"]
        if "image" in e:
            env = EquirectEnvironment.from_file(path.parent / e["image"], yaw=float(e.get("yaw", 0.0)),
                                                pitch=float(e.get("pitch", 0.0)), roll=float(e.get("roll", 0.0)),
                                                scale=float(e.get("scale", 1.0)))
        else:
            env = ConstantEnvironment(e.get("radiance", 1.0))
    views = {}
    for name, c in doc.get("cameras", {}).items():
        views[name] = View(eye=tuple(c.get("eye", (0, 0, 0))), look_at=tuple(c.get("look_at", (0, 0, 1))),
                           up=tuple(c.get("up", (0, 1, 0))), lens=c.get("lens", "perspective:fov=60"))
    if not parts and env is None:
        raise SceneError(f"{path}: the scene has no [[mesh]] and no [environment]")
    return merge_meshes(parts, environment=env, point_lights=lights, views=views,
                        name=head.get("name", path.stem), dropped=dropped)
