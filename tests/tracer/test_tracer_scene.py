"""Scenes: built-ins, OBJ/MTL, PLY/STL and TOML loading, clear errors, determinism, and the command line."""

from __future__ import annotations

import itertools
import types

import numpy as np
import pytest

import tracer
from tracer.cli import main
from tracer.scene import SceneError

OBJ = """\
mtllib box.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 0 0 1
usemtl lamp
f 1 2 3 4
usemtl shiny
f 1 2 6
usemtl mirror
f -6/1/1 -5/2/2 -1/3/3
f 1 2 5
"""

MTL = """\
newmtl lamp
Kd 0.1 0.1 0.1
Ka 5 5 5
newmtl shiny
Kd 0.5 0.5 0.5
Ks 0.7 0.7 0.7
Ns 30
newmtl mirror
Ks 0.9 0.9 0.9
illum 3
"""


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_cornell_box_has_the_published_layout():
    s = tracer.load_scene("cornell")
    lo, hi = s.bounds
    np.testing.assert_allclose(hi - lo, [0.556, 0.5488, 0.5592], atol=1e-9)  # published extents, mm -> m, float64
    assert {m.name for m in s.materials} == {"white", "red", "green", "light"}
    # the light: 130 x 105 mm, facing down
    np.testing.assert_allclose(s.areas[s.light_triangles].sum(), 0.130 * 0.105, rtol=1e-9)  # float64 cross products
    assert np.all(s.normals[s.light_triangles] @ [0, 1, 0] < -0.999)
    # red wall on the camera's left: its x is below the camera's
    red = s.material_ids == [m.name for m in s.materials].index("red")
    assert s.vertices[s.triangles[red]].reshape(-1, 3)[:, 0].max() < s.views["default"].eye[0]


def test_obj_with_mtl(tmp_path):
    write(tmp_path, "box.mtl", MTL)
    path = write(tmp_path, "box.obj", OBJ)
    s = tracer.load_scene(path)
    kinds = {m.name: m.kind for m in s.materials}
    assert kinds == {"lamp": "diffuse", "shiny": "glossy", "mirror": "mirror"}
    assert len(s.triangles) == 2 + 1 + 1  # the quad is triangulated
    assert s.dropped == 1  # f -6 -5 -1 is (0,0,0) (1,0,0) (2,0,0): collinear
    glossy = next(m for m in s.materials if m.name == "shiny")
    assert max(np.add(glossy.kd, glossy.ks)) <= 1 + 1e-9  # scaled to conserve energy
    assert not s.has_area_lights
    lit = tracer.load_scene(path, ambient_as_emission=True)
    assert lit.has_area_lights and len(lit.light_triangles) == 2


def test_obj_errors_are_clear(tmp_path):
    path = write(tmp_path, "a.obj", "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(SceneError, match="missing.mtl"):
        tracer.load_scene(path)
    write(tmp_path, "b.mtl", "newmtl known\nKd 1 1 1\n")
    path = write(tmp_path, "b.obj", "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl nope\nf 1 2 3\n")
    with pytest.raises(SceneError, match="nope.*known"):
        tracer.load_scene(path)
    path = write(tmp_path, "c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(SceneError, match="vertex 7"):
        tracer.load_scene(path)
    with pytest.raises(FileNotFoundError):
        tracer.load_scene(tmp_path / "none.obj")
    with pytest.raises(SceneError, match="built-in"):
        tracer.load_scene("no-such-scene")


def test_ply_and_stl_through_pyvista(tmp_path):
    import pyvista as pv

    mesh = pv.Sphere(radius=0.5, theta_resolution=12, phi_resolution=12)
    for ext in ("ply", "stl"):
        path = tmp_path / f"ball.{ext}"
        mesh.save(str(path))
        s = tracer.load_scene(path)
        assert len(s.triangles) == mesh.triangulate().n_cells
        assert s.materials[0].kind == "diffuse"
        np.testing.assert_allclose(s.areas.sum(), mesh.area, rtol=1e-5)  # STL stores float32 vertices


def test_toml_scene(tmp_path):
    write(tmp_path, "s.toml", """
[scene]
name = "demo"

[materials.floor]
kd = [0.5, 0.5, 0.5]

[materials.lamp]
kd = 0.0
emission = [4.0, 4.0, 4.0]

[[mesh]]
shape = "quad"
points = [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]
facing = [0, 1, 0]
material = "floor"

[[mesh]]
shape = "quad"
points = [[-0.1, 1, -0.1], [0.1, 1, -0.1], [0.1, 1, 0.1], [-0.1, 1, 0.1]]
facing = [0, -1, 0]
material = "lamp"

[environment]
radiance = 0.1

[cameras.top]
lens = "perspective:fov=30"
eye = [0.0, 0.5, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
""")
    s = tracer.load_scene(tmp_path / "s.toml")
    assert s.name == "demo" and len(s.triangles) == 4 and s.has_area_lights
    cam = s.camera(size=(8, 8), view="top")
    res = tracer.render(s, cam, spp=4, seed=0)
    assert res.image.shape == (8, 8, 3) and np.all(res.image > 0)

    write(tmp_path, "bad.toml", '[[mesh]]\nshape = "quad"\npoints = [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]\nmaterial = "x"\n')
    with pytest.raises(SceneError, match="unknown material 'x'"):
        tracer.load_scene(tmp_path / "bad.toml")


def test_fixed_seed_gives_identical_images_whatever_the_threads():
    s = tracer.load_scene("sky")
    cam = s.camera(size=(24, 16))
    a = tracer.render(s, cam, spp=4, seed=11, threads=1, batch=500)
    b = tracer.render(s, cam, spp=4, seed=11, threads=2, batch=500)
    np.testing.assert_array_equal(a.image, b.image)
    c = tracer.render(s, cam, spp=4, seed=12, threads=2, batch=500)
    assert not np.array_equal(a.image, c.image)


def test_variance_tracking_matches_the_spread_of_independent_renders():
    """The reported variance of each pixel's mean predicts how much renders with other seeds differ."""
    s = tracer.load_scene("plane")  # uniform radiance: all noise comes from light transport, none from strata
    cam = s.camera(size=(12, 12))
    runs = [tracer.render(s, cam, spp=16, seed=k, max_depth=2) for k in range(8)]
    spread = np.var([r.image for r in runs], axis=0, ddof=1).mean()
    reported = np.mean([r.variance for r in runs])
    # 8 renders x 144 pixels x 3 channels: the empirical variance is good to about 5%
    assert 0.8 * spread < reported < 1.25 * spread
    # where pixels hold edges, stratified sampling beats the per-sample variance: the report is conservative
    s = tracer.load_scene("cornell")
    cam = s.camera(size=(12, 12))
    runs = [tracer.render(s, cam, spp=16, seed=k, max_depth=2) for k in range(6)]
    spread = np.var([r.image for r in runs], axis=0, ddof=1).mean()
    assert np.mean([r.variance for r in runs]) > 0.8 * spread


@pytest.fixture
def ticking_clock(monkeypatch):
    """The renderer's clock advances 10 ms each time it is read, whatever the machine's speed or load:
    a time budget then ends after a fixed number of readings (a state), never after a real duration."""
    ticks = itertools.count()
    monkeypatch.setattr("tracer.rendering.time", types.SimpleNamespace(perf_counter=lambda: 0.01 * next(ticks)))


def test_time_budget_and_target_error_stop_early(ticking_clock):
    s = tracer.load_scene("plane")
    cam = s.camera(size=(8, 8))
    res = tracer.render(s, cam, spp=4096, seed=0, target_error=0.05)
    assert res.stopped_by == "error" and res.spp < 4096 and res.relative_error <= 0.05
    res = tracer.render(s, cam, spp=1 << 20, seed=0, time_budget=0.2)
    # 0.2 s of a clock read once per pass (plus once at the start and once at the end): 19 passes at most
    assert res.stopped_by == "time" and 2 <= res.spp < 1 << 20 and res.seconds <= 0.22


def test_cli_render_writes_exr_with_camera(tmp_path):
    import OpenEXR

    from lenslab.lenses import Camera

    out, var = tmp_path / "c.exr", tmp_path / "v.exr"
    rc = main(["render", "--scene", "cornell", "--camera", "fisheye:fov=180", "--size", "24x16", "--spp", "2",
               "--yaw", "10", "-o", str(out), "--variance-out", str(var), "-q"])
    assert rc == 0 and out.is_file() and var.is_file()
    with OpenEXR.File(str(out)) as f:
        header = f.header()
        px = np.array(next(iter(f.channels().values())).pixels)
        cam_attr = header.get("lenslab.camera")
    assert cam_attr is not None
    cam = Camera.from_toml(cam_attr if isinstance(cam_attr, str) else cam_attr.decode())
    assert cam.lens.name == "fisheye" and cam.size == (24, 16)
    assert abs(cam.pose.ypr[0] - 10) < 1e-9
    assert px.shape[:2] == (16, 24) and np.isfinite(px).all()


def test_cli_errors_are_reported(tmp_path, capsys):
    assert main(["render", "--scene", "nowhere", "-o", str(tmp_path / "x.exr"), "-q"]) == 2  # no such name: usage
    assert "tracer render: error:" in capsys.readouterr().err
    assert main(["render", "--scene", str(tmp_path / "gone.obj"), "-o", str(tmp_path / "x.exr"), "-q"]) == 1  # input
    assert "no such scene file" in capsys.readouterr().err
    assert main(["render", "--camera", "fisheye:fov=-3", "-o", str(tmp_path / "x.exr"), "-q"]) == 2  # a bad spec: usage
    assert not (tmp_path / "x.exr").exists()


def test_cli_camera_file_and_time_budget(tmp_path, ticking_clock):
    import OpenEXR

    from lenslab.lenses import Camera

    cams = tmp_path / "cams.toml"
    wide = Camera.from_spec("equirect", (32, 16), eye=(0.278, 0.27, 0.3))
    near = Camera.from_spec("perspective:fov=50", (20, 20), eye=(0.1, 0.2, 0.1), look_at=(0.4, 0.2, 0.5))
    cams.write_text("[wide]\n" + wide.to_toml().replace("\n[lens]", "\n[wide.lens]")
                    + "\n[near]\n" + near.to_toml().replace("\n[lens]", "\n[near.lens]"))
    out = tmp_path / "n.exr"
    rc = main(["render", "--camera-file", str(cams), "--view", "near", "--spp", "100000",
               "--time-budget", "0.3", "-o", str(out), "-q"])
    assert rc == 0
    with OpenEXR.File(str(out)) as f:
        header = f.header()
        cam = Camera.from_toml(header["lenslab.camera"])
        spp = int(header["tracer.spp"])
    assert cam.lens == near.lens
    np.testing.assert_allclose(cam.pose.rotation, near.pose.rotation, atol=1e-12)  # via yaw/pitch/roll in TOML
    np.testing.assert_allclose(cam.pose.eye, near.pose.eye)
    assert 2 <= spp < 100000


def test_import_is_light_and_the_entry_points_exist():
    import subprocess
    import sys

    code = ("import sys, tracer; heavy = [m for m in ('numpy', 'pyvista', 'embreex', 'OpenEXR') if m in sys.modules]; "
            "print(heavy); tracer.render, tracer.load_scene, tracer.RenderResult")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_cli_display_output_is_tone_mapped(tmp_path):
    from lenslab.io import read
    from lenslab.tone import tonemap

    out, hdr = tmp_path / "c.png", tmp_path / "c.exr"
    args = ["render", "--size", "16x16", "--spp", "2", "--seed", "4", "-q"]
    assert main(args + ["-o", str(out), "--tone", "reinhard", "--exposure", "1"]) == 0
    assert main(args + ["-o", str(hdr)]) == 0
    png, _ = read(out)
    radiance, _ = read(hdr)
    # the same render, tone mapped then 8-bit sRGB encoded: within half an 8-bit step after decoding
    # (in linear light the step is largest near white, 1 - srgb_decode(254.5 / 255) ~ 0.0045)
    np.testing.assert_allclose(png, tonemap(radiance, "reinhard", exposure=1.0), atol=0.005)
