"""Scenes read in their tool's handedness: an OBJ from a right-handed tool renders in the tracer as Mitsuba 3
renders it (the same image, not its mirror); a left-handed asset is kept with the documented switch."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio

W, H, FOV = 120, 80, 50.0
QUAD_X = 0.25  # the emitter's centre, right-handed tool coordinates: +x is to the camera's left there


def write_quad_obj(path, x=QUAD_X, half=0.05, z=1.0):
    """A small emitting square at (x, 0, z) facing the origin (its normal -z by the right-hand rule)."""
    (path.parent / "q.mtl").write_text("newmtl light\nKd 0 0 0\nKe 1 1 1\n")
    x0, x1, y0, y1 = x - half, x + half, -half, half
    path.write_text("mtllib q.mtl\nusemtl light\n"
                    f"v {x0} {y0} {z}\nv {x0} {y1} {z}\nv {x1} {y1} {z}\nv {x1} {y0} {z}\nf 1 2 3\nf 1 3 4\n")
    return path


def write_quad_ply(path, x=QUAD_X, half=0.05, z=1.0):
    """The same square as an ASCII PLY (PLY carries no material: the tracer shows it lit by its sky, Mitsuba
    is given an emitter for it)."""
    x0, x1, y0, y1 = x - half, x + half, -half, half
    verts = [(x0, y0, z), (x0, y1, z), (x1, y1, z), (x1, y0, z)]
    path.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                    + "".join(f"{a} {b} {c}\n" for a, b, c in verts) + "3 0 1 2\n3 0 2 3\n")
    return path


def column_centroid(img):
    lum = np.asarray(img, np.float64)[..., :3].sum(-1)
    cols = lum.sum(0)
    assert cols.sum() > 0, "the emitter is not in the image"
    return float((cols * (np.arange(img.shape[1]) + 0.5)).sum() / cols.sum())


def tracer_render(scene, out, *extra):
    r = subprocess.run([sys.executable, "-m", "tracer.cli", "render", "--scene", str(scene), "--camera",
                        f"perspective:fov={FOV:g}", "--size", f"{W}x{H}", "--eye", "0,0,0", "--look-at", "0,0,1",
                        "--spp", "16", "--integrator", "direct", "-o", str(out), "-q", *extra],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return lio.read(out)[0]


def mitsuba_render(obj, kind="obj"):
    mi = pytest.importorskip("mitsuba")
    mi.set_variant("scalar_rgb")
    try:
        to_world = mi.ScalarTransform4f().look_at(origin=[0, 0, 0], target=[0, 0, 1], up=[0, 1, 0])
    except TypeError:  # Mitsuba before 3.6: a static method
        to_world = mi.ScalarTransform4f.look_at(origin=[0, 0, 0], target=[0, 0, 1], up=[0, 1, 0])
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "direct"},
        "sensor": {"type": "perspective", "fov": FOV, "fov_axis": "x", "to_world": to_world,
                   "film": {"type": "hdrfilm", "width": W, "height": H, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": 16}},
        "quad": {"type": kind, "filename": str(obj),
                 "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}}},
    })
    return np.asarray(mi.render(scene))


def test_right_handed_obj_renders_as_mitsuba_shows_it(tmp_path):
    obj = write_quad_obj(tmp_path / "q.obj")
    ref = column_centroid(mitsuba_render(obj))
    got = column_centroid(tracer_render(obj, tmp_path / "t.exr"))
    # the quad's column from the perspective formula, transcribed: Mitsuba's look_at puts +x on the left,
    # x_pix = W/2 * (1 - (x/z) / tan(fov/2))
    analytic = W / 2 * (1 - QUAD_X / np.tan(np.radians(FOV) / 2))
    assert abs(ref - analytic) < 0.5  # Mitsuba agrees with the formula (box filter, 16 spp)
    # 0.5 px: both images are box-filtered pixel averages of the same 10.7 px wide square
    assert abs(got - ref) < 0.5, (got, ref)


def test_left_handed_switch_keeps_the_asset_as_it_is(tmp_path):
    obj = write_quad_obj(tmp_path / "q.obj")
    got = column_centroid(tracer_render(obj, tmp_path / "t.exr", "--handedness", "left"))
    # lenslab's own frame: +x to the right, x_pix = W/2 * (1 + (x/z) / tan(fov/2))
    assert abs(got - W / 2 * (1 + QUAD_X / np.tan(np.radians(FOV) / 2))) < 0.5


def test_mirroring_keeps_faces_facing_the_same_way():
    from tracer.load import mirror_to_left_handed

    v = np.array([[0.2, -0.05, 1.0], [0.2, 0.05, 1.0], [0.3, 0.05, 1.0]])
    t = np.array([[0, 1, 2]])
    mv, mt = mirror_to_left_handed(v, t)
    a, b, c = mv[mt[0]]
    n = np.cross(b - a, c - a)
    assert n[2] < 0 and np.allclose(mv[:, 0], -v[:, 0])  # still faces the camera at the origin


def test_right_handed_ply_lands_where_mitsuba_puts_it(tmp_path):
    # a bare PLY: the tracer lights it with its uniform sky, so the square is bright on a bright sky;
    # the column is found in the difference from the same render without the square
    ply = write_quad_ply(tmp_path / "q.ply")
    ref = column_centroid(mitsuba_render(ply, "ply"))
    got = tracer_render(ply, tmp_path / "t.exr")
    assert abs(ref - W / 2 * (1 - QUAD_X / np.tan(np.radians(FOV) / 2))) < 0.5
    # the square hides the sky behind it: its pixels are the ones below the sky's radiance
    hidden = (got[..., :3].mean(-1) < 0.5).astype(np.float64)
    assert abs(column_centroid(hidden[..., None].repeat(3, -1)) - ref) < 0.5
