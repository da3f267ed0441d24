"""The lens registry and spec syntax, serialisation of lenses and cameras (TOML, tiled ones included),
camera rays of tiled cameras, and the ``lenslab lenses`` listing."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab_main
from lenslab.errors import LensError
from lenslab.lenses import (REGISTRY, Camera, Pose, load_camera, load_cameras, make_lens, parse_spec,
                            save_camera, save_cameras)
from tests.lenses.test_lenses_roundtrip import CASES


# -- specs ---------------------------------------------------------------------------------------
def test_unknown_model_lists_the_valid_ones():
    with pytest.raises(LensError) as err:
        make_lens("fishey:fov=180", (64, 64))
    for name in REGISTRY:
        assert name in str(err.value)


@pytest.mark.parametrize("spec,valid", [
    ("fisheye:fov=180,mappin=equisolid", ["fov", "mapping"]),
    ("swirl:amount=6,strength=2", ["amount", "base", "fov", "vfov"]),
    ("swirl:base=fisheye,k1=3", ["amount", "base", "fov", "mapping"]),
    ("pincushion:k3=0.1", ["k1", "k2", "base", "fov"]),
    ("cubemap:faces=6", ["layout", "order"]),
    ("tiled:2x2,lens=fisheye", ["grid", "tiles"]),
])
def test_unknown_parameter_lists_the_valid_ones(spec, valid):
    with pytest.raises(LensError) as err:
        make_lens(spec, (64, 64))
    for name in valid:
        assert name in str(err.value)


@pytest.mark.parametrize("spec", [
    "fisheye:fov=361", "fisheye:fov=0", "fisheye:fov=360,mapping=stereographic",
    "fisheye:fov=181,mapping=orthographic", "fisheye:mapping=polar", "perspective:fov=180",
    "seedfisheye:fov=181", "pincushion:k1=-0.1", "barrel:k1=0.2", "barrel:k1=0", "swirl:amount=nan",
    "swirl:amount=inf", "cubemap:order=rludff", "cubemap:layout=5x2", "tiled:0x2", "tiled:2by2",
    "swirl:base=cubemap", "distortion:base=tiled", "fisheye:fov=abc", "fisheye:fov", "equirect:lon_min=10,lon_max=5",
])
def test_bad_values_are_refused(spec):
    with pytest.raises(LensError):
        make_lens(spec, (60, 60))


def test_specs_from_the_docs_parse():
    lens = make_lens("pincushion:k1=0.3,k2=0.05,fov=90", (800, 600))
    assert (lens.k1, lens.k2, lens.base_lens.name, lens.base_lens.fov) == (0.3, 0.05, "perspective", 90.0)
    sw = make_lens("swirl:amount=6,base=fisheye,fov=180,mapping=equisolid", (512, 512))
    assert sw.amount == 6.0 and sw.base_lens.mapping == "equisolid" and sw.base_lens.fov == 180.0
    assert make_lens("swirl:amount=6", (10, 10)).base_lens.name == "perspective"
    assert make_lens("tiled:3x2", (60, 40)).cols == 3
    assert parse_spec("tiled:2x2,tiles=a.toml") == ("tiled", {"grid": "2x2", "tiles": "a.toml"})
    assert parse_spec("fisheye: fov = 200 , mapping=equisolid") == ("fisheye", {"fov": "200", "mapping": "equisolid"})
    assert make_lens("pincushion", (10, 10)).k1 > 0 and make_lens("barrel", (10, 10)).k1 < 0
    # tiled sizes must split into whole tiles
    with pytest.raises(LensError):
        make_lens("tiled:3x1", (100, 50))


@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_spec_and_dict_round_trip(spec, size):
    lens = make_lens(spec, size)
    assert make_lens(lens.to_dict()) == lens
    assert make_lens(lens.spec(), size) == lens
    assert lens.with_size(*size) == lens
    # the spec reads back to the same floats, written short (0.3, not 0.29999999999999999)
    assert "9999999" not in lens.spec()


# -- cameras in TOML -----------------------------------------------------------------------------
def seed_like_tiled_camera(tmp_path):
    """The seed's 2x2 instance: four perspective cameras at different eye points, as a tiles file."""
    tiles = tmp_path / "cams.toml"
    tiles.write_text('''
[[tiles]]
lens = "perspective:fov=60"
eye = [0.0, 4.0, 0.0]
at = [0.35, 4.5, 0.8]

[[tiles]]
lens = { model = "fisheye", fov = 180.0, mapping = "equisolid" }
eye = [2.5, 4.75, 5.5]
yaw = 30.0
pitch = -10.0

[[tiles]]

[[tiles]]
lens = "swirl:amount=3,fov=70"
eye = [2.13, 4.25, 2.0]
roll = 15.0
''')
    lens = make_lens(f"tiled:2x2,tiles={tiles}", (400, 300))
    return Camera(lens, Pose.from_ypr(10.0, 5.0, 0.0, eye=(1.0, 2.0, 3.0))), tiles


def test_tiled_from_tiles_file(tmp_path):
    cam, tiles = seed_like_tiled_camera(tmp_path)
    lens = cam.lens
    assert lens.spec() == f"tiled:2x2,tiles={tiles}"
    assert [t is None for t in lens.tile_list] == [False, False, True, False]
    assert (lens.tile_list[0].lens.width, lens.tile_list[0].lens.height) == (200, 150)
    # tile 2 has no camera: its pixels are invalid
    d, ok = lens.pixel_to_dir([[50.0, 50.0], [50.0, 200.0], [300.0, 50.0]])
    assert list(ok) == [True, False, True] and (d[1] == 0).all()
    # the distinct eye points, and each pixel's origin is its tile's eye
    assert {tuple(e) for e in lens.eye_offsets} == {(0.0, 4.0, 0.0), (2.5, 4.75, 5.5), (2.13, 4.25, 2.0)}
    assert np.allclose(lens.pixel_origin([[10.0, 10.0], [390.0, 290.0]]), [[0, 4, 0], [2.13, 4.25, 2.0]])


def test_tiled_camera_rays_have_per_tile_origins(tmp_path):
    cam, _ = seed_like_tiled_camera(tmp_path)
    origins, dirs, valid = cam.rays(samples=4, seed=None)
    assert origins.shape == (300, 400, 4, 3) and dirs.shape == (300, 400, 4, 3) and valid.shape == (300, 400, 4)
    R, eye = cam.pose.rotation, cam.pose.eye
    for (r0, c0), tile_eye in (((0, 0), (0, 4, 0)), ((0, 200), (2.5, 4.75, 5.5)), ((150, 200), (2.13, 4.25, 2.0))):
        block = origins[r0:r0 + 150, c0:c0 + 200]
        assert np.allclose(block, R @ np.array(tile_eye, dtype=float) + eye, atol=1e-12)
    assert not valid[150:, :200].any()  # the empty tile
    # tile 0 looks from its eye toward its target: its centre ray points at (0.35, 4.5, 0.8) - eye
    centre = Camera(cam.lens).pixel_to_world([[100.0, 75.0]])[1][0]
    expect = np.array([0.35, 0.5, 0.8]) / np.linalg.norm([0.35, 0.5, 0.8])
    assert np.allclose(centre, expect, atol=1e-12)


def test_tiled_dir_to_pixel_takes_the_first_tile_that_sees(tmp_path):
    lens = make_lens({"model": "tiled", "grid": "2x1", "tiles": [
        {"lens": "perspective:fov=90"}, {"lens": "perspective:fov=60", "eye": [1.0, 0.0, 0.0]}]}, (200, 100))
    xy, ok = lens.dir_to_pixel([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    assert list(ok) == [True, False] and np.allclose(xy[0], [50.0, 50.0])


def assert_same_camera(a, b):
    """Same lens models, sizes and tiling; the same rays to 1e-12. Poses are written as yaw, pitch and
    roll, whose conversion from a matrix and back may move the last bit, hence not exact equality."""
    assert type(a.lens) is type(b.lens) and a.size == b.size
    if a.lens.name == "tiled":
        assert a.lens.grid == b.lens.grid
        assert [t and t.lens for t in a.lens.tile_list] == [t and t.lens for t in b.lens.tile_list]
    else:
        assert a.lens == b.lens
    assert np.allclose(a.lens.eye_offsets, b.lens.eye_offsets, atol=1e-12)
    xy = np.random.default_rng(0).random((500, 2)) * a.size
    for u, v in zip(a.pixel_to_world(xy), b.pixel_to_world(xy)):
        assert np.allclose(u, v, atol=1e-12)


def test_camera_toml_round_trip_with_tiles(tmp_path):
    cam, _ = seed_like_tiled_camera(tmp_path)
    text = cam.to_toml()  # what image headers store
    again = Camera.from_toml(text)
    assert_same_camera(again, cam)
    # files
    path = save_camera(tmp_path / "cam.toml", cam)
    assert_same_camera(load_camera(path), cam)
    assert not list(tmp_path.glob(".cam.tmp-*"))  # written through a temporary file, renamed


def test_camera_files_with_several_cameras(tmp_path):
    cams = [Camera.from_spec("fisheye:fov=200,mapping=equisolid", (64, 64), yaw=30, eye=(1, 2, 3)),
            Camera.from_spec("pincushion:k1=0.3,k2=0.05,fov=90", (80, 60), look_at=(0, 0, 5), eye=(0, 1, 0))]
    path = save_cameras(tmp_path / "rig.toml", cams)
    back = load_cameras(path)
    assert len(back) == 2
    for a, b in zip(back, cams):
        assert_same_camera(a, b)
    with pytest.raises(LensError):
        load_camera(path)  # two cameras where one was expected
    (tmp_path / "hand.toml").write_text('lens = "fisheye:fov=180"\nsize = [100, 100]\nyaw = 90.0\n')
    hand = load_camera(tmp_path / "hand.toml")
    assert hand.lens.fov == 180.0 and np.allclose(hand.pose.rotation[:, 2], [1, 0, 0])
    # a hand-written tiled camera names its tiles file relative to itself
    sub = tmp_path / "rig"
    sub.mkdir()
    (sub / "tiles.toml").write_text('[[tiles]]\nlens = "perspective:fov=50"\neye = [0.0, 1.0, 0.0]\n')
    (sub / "cam.toml").write_text('lens = "tiled:2x1,tiles=tiles.toml"\nsize = [200, 100]\n')
    tiled = load_camera(sub / "cam.toml")
    assert tiled.lens.tile_list[0].lens.fov == 50.0 and tiled.lens.tile_list[1] is None
    assert np.array_equal(tiled.lens.eye_offsets, [[0.0, 1.0, 0.0]])
    (tmp_path / "bad.toml").write_text("yaw = 1\n")
    with pytest.raises(LensError):
        load_cameras(tmp_path / "bad.toml")


# -- the command ---------------------------------------------------------------------------------
def test_lenses_command_lists_every_model_and_parameter(capsys):
    assert lenslab_main(["lenses"]) == 0
    out = capsys.readouterr().out
    for name, cls in REGISTRY.items():
        assert f"{name}: " in out
        for p in cls.params:
            assert p.name in out
    fov_line = next(line for line in out.splitlines() if "(the image circle)" in line)
    assert "(0, 360]" in fov_line  # fisheye fov range, open at 0
    assert lenslab_main(["lenses", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {m["name"] for m in data} == set(REGISTRY)
    assert lenslab_main(["lenses", "seedfisheye"]) == 0
    assert "144.7" in capsys.readouterr().out  # the full description, with the fold
    assert lenslab_main(["lenses", "nosuch"]) == 2  # an unknown model name: a usage error
