"""v360's mirrors and rotation order against Debian's ffmpeg: ``h_flip``/``v_flip``/``d_flip`` (lenslab
``--flip``), ``ih_flip``/``iv_flip`` (``--source-flip``) and ``rorder`` (``--rotation-order``), within the
tolerance of the other v360 projections (``tests/warp/test_v360_ffmpeg.py`` explains ``TOL`` and ``EDGE``)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from tests.warp.test_v360_ffmpeg import assert_matches_ffmpeg, fragile, run_ffmpeg, source_codes
from tests.warp.test_v360_stereo import two_eyes


def run_lenslab(tmp_path, codes, src_spec, dst_spec, size, extra):
    src, out = tmp_path / "ll_in.exr", tmp_path / "ll_out.exr"
    write(src, codes.astype(np.float32) / 255, pixel_type="float", overwrite=True)
    assert main(["warp", str(src), "--from", src_spec, "--to", dst_spec, "--size", f"{size[0]}x{size[1]}",
                 "--compat", "v360", "--pixel-type", "float", "-o", str(out), "-q", "--overwrite", *extra]) == 0
    img = read(out)[0]
    return img[..., :3].astype(np.float64) * 255, img[..., 3]


VIEW = [  # (v360 options, lenslab options); v360's roll turns the other way (docs/v360.md)
    ("h_flip=1", ["--flip", "h"]),
    ("v_flip=1", ["--flip", "v"]),
    ("d_flip=1", ["--flip", "d"]),
    ("h_flip=1:v_flip=1:d_flip=1:yaw=20:pitch=-10", ["--flip", "h,v,d", "--yaw", "20", "--pitch", "-10"]),
    ("rorder=rpy:yaw=30:pitch=20:roll=25", ["--rotation-order", "rpy", "--yaw", "30", "--pitch", "20", "--roll", "-25"]),
    ("rorder=pyr:yaw=30:pitch=20:roll=25", ["--rotation-order", "pyr", "--yaw", "30", "--pitch", "20", "--roll", "-25"]),
    ("rorder=ryp:yaw=-40:pitch=35:roll=10", ["--rotation-order", "ryp", "--yaw", "-40", "--pitch", "35", "--roll", "-10"]),
]


@pytest.mark.parametrize("opts,flags", VIEW, ids=[v[0] for v in VIEW])
def test_view_mirrors_and_rotation_order_match_ffmpeg(tmp_path, opts, flags):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg(tmp_path, codes, f"input=e:output=flat:h_fov=100:v_fov=100:{opts}", (48, 48))
    ours, alpha = run_lenslab(tmp_path, codes, "equirect", "perspective:fov=100", (48, 48), flags)
    assert_matches_ffmpeg(ours, alpha, theirs, np.zeros((48, 48), dtype=bool))


SOURCES = [  # (lenslab spec, v360 input, size): a whole-frame projection, cube maps, two halves, EAC
    ("equirect", "e", (128, 64)),
    ("fisheye:fov=180", "fisheye:ih_fov=180:iv_fov=180", (64, 64)),
    ("cubemap", "c3x2", (96, 64)),
    ("dual-fisheye:fov=190,front=right", "dfisheye:ih_fov=190:iv_fov=190", (128, 64)),
    ("eac:pad=2", "eac", (96, 64)),
]
FLIPS = [("ih_flip=1", "h"), ("iv_flip=1", "v"), ("ih_flip=1:iv_flip=1", "h,v")]
CASES = [(s, f) for s in SOURCES for f in FLIPS]


@pytest.mark.slow
@pytest.mark.parametrize("source,flip", CASES, ids=[f"{s[1].split(':')[0]}-{f[0]}" for s, f in CASES])
def test_source_mirrors_match_ffmpeg(tmp_path, source, flip):
    spec, v360, size = source
    codes = source_codes(*size)
    theirs = run_ffmpeg(tmp_path, codes, f"input={v360}:{flip[0]}:output=e", (96, 48))
    ours, alpha = run_lenslab(tmp_path, codes, spec, "equirect", (96, 48), ["--source-flip", flip[1]])
    assert_matches_ffmpeg(ours, alpha, theirs, fragile(spec, size, "equirect", (96, 48)))


def test_stereo_source_is_mirrored_per_eye(tmp_path):
    codes = two_eyes(64, 64, "sbs")
    theirs = run_ffmpeg(tmp_path, codes, "input=hequirect:in_stereo=sbs:ih_flip=1:output=e", (96, 48))
    ours, alpha = run_lenslab(tmp_path, codes, "stereo:sbs,base=half-equirect", "equirect", (96, 48),
                              ["--source-flip", "h"])
    assert_matches_ffmpeg(ours, alpha, theirs, fragile("half-equirect", (64, 64), "equirect", (96, 48)))


def test_flips_are_mirror_images(tmp_path):
    """Without --compat: an h-mirrored perspective view is the unmirrored view reversed left to right (a
    perspective lens is symmetric), exactly; and flip letters are checked."""
    rng = np.random.default_rng(3)
    pano = rng.random((32, 64, 3)).astype(np.float32)
    src = tmp_path / "pano.exr"
    write(src, pano, pixel_type="float")
    outs = {}
    for flag in ("", "h", "v"):
        out = tmp_path / f"out{flag}.exr"
        args = ["warp", str(src), "--to", "perspective:fov=80", "--size", "24x24", "--pixel-type", "float",
                "--filter", "nearest", "-o", str(out), "-q"] + (["--flip", flag] if flag else [])
        assert main(args) == 0
        outs[flag] = read(out)[0]
    np.testing.assert_array_equal(outs["h"], outs[""][:, ::-1])
    np.testing.assert_array_equal(outs["v"], outs[""][::-1])
    assert main(["warp", str(src), "--to", "perspective", "-o", str(tmp_path / "x.exr"), "--flip", "q", "-q"]) == 2
