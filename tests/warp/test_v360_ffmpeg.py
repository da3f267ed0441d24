"""``lenslab warp --compat v360`` against Debian's ffmpeg ``v360`` filter, every shared projection both
ways (as the source, read into an equirect; as the output, made from an equirect).

The source is a smooth 8-bit RGB image. ffmpeg converts it in planar RGB (``format=gbrp``: no YUV
rounding) with ``interp=line``; lenslab warps the same values as floats (an EXR of ``code / 255``) and
the two outputs are compared in code values. ffmpeg is part of CI (``.ci/run`` installs it), so it is
required here, not skipped.
"""

from __future__ import annotations

import math
import shutil
import subprocess

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera
from lenslab.warp.maps import exact_map

#: ffmpeg's bilinear sums 14-bit integer weights (16385 in all, lrintf of float products) and drops
#: the fraction (``>> 14``): up to 1 code below the exact value plus ~0.05 from the weights; v360's
#: float32 map is ~1e-3 px from the float64 one, 0.01 code at this image's steepest 8 codes/px
TOL = 1.1
#: output pixels left out of the comparison: those whose sample lies within this many source pixels
#: of a place where the two disagree by design (a cube face's edge: both read the neighbouring face, v360
#: the nearest pixel of it, lenslab its continuation, interpolated; the edge of the source's valid
#: region, where v360 and lenslab decide visibility from float32 and float64 numbers)
EDGE = 1.5

PAN = 4 * math.degrees(math.atan(0.5))  # Pannini d = 1: x = 2 tan(phi/2) = 1 at the edge, phi = 2 atan(1/2)

#: (lenslab spec, v360 projection with its options, size): the options are written for the output side
#: (h_fov, v_fov, d_fov); the input side uses ih_fov, iv_fov, id_fov
SHARED = [
    ("equirect", "e", (128, 64)),
    ("half-equirect", "hequirect", (64, 64)),
    ("perspective:fov=90", "flat:h_fov=90:v_fov=90", (64, 64)),
    ("perspective:dfov=100", "flat:d_fov=100", (96, 64)),
    ("fisheye:fov=180", "fisheye:h_fov=180:v_fov=180", (64, 64)),
    # a full-frame fisheye on a 3:2 frame; v360's d_fov scales fisheyes by d/h and d/w, right only on
    # square frames, so its h_fov and v_fov are given: dfov times the half width (height) over the half diagonal
    ("fisheye:dfov=200", f"fisheye:h_fov={200 * 48 / math.hypot(48, 32)!r}:v_fov={200 * 32 / math.hypot(48, 32)!r}",
     (96, 64)),
    ("fisheye:dfov=250", "fisheye:d_fov=250", (64, 64)),  # v360's d_fov holds on square frames
    ("fisheye:fov=180,mapping=stereographic", "sg:h_fov=180:v_fov=180", (64, 64)),
    ("fisheye:fov=200,mapping=equisolid", "equisolid:h_fov=200:v_fov=200", (64, 64)),
    ("fisheye:fov=160,mapping=orthographic", "og:h_fov=160:v_fov=160", (64, 64)),
    ("cubemap", "c3x2", (96, 64)),
    ("cubemap:layout=6x1", "c6x1", (192, 32)),
    ("cubemap:layout=1x6", "c1x6", (32, 192)),
    ("eac:pad=2", "eac", (96, 64)),
    ("dual-fisheye:fov=190,front=right", "dfisheye:h_fov=190:v_fov=190", (128, 64)),
    ("cylindrical:fov=180,vfov=100", "cylindrical:h_fov=180:v_fov=100", (64, 64)),
    ("cylindrical-equal-area:vfov=180", "cylindricalea", (128, 64)),
    ("mercator", "mercator", (64, 64)),
    (f"mercator:vfov={2 * math.degrees(math.atan(math.sinh(math.pi)))!r}", "mercator", (128, 64)),
    (f"pannini:d=1,fov={PAN!r}", "pannini:h_fov=1", (64, 64)),
    ("hammer", "hammer", (128, 64)),
    ("sinusoidal", "sinusoidal", (128, 64)),
    ("octahedron", "octahedron", (64, 64)),
]


def ffmpeg() -> str:
    path = shutil.which("ffmpeg")
    assert path, "ffmpeg is needed (CI installs Debian's); apt-get install ffmpeg"
    return path


def source_codes(w: int, h: int) -> np.ndarray:
    """A smooth 8-bit RGB image (at most ~8 codes per pixel), the same in both tools."""
    y, x = np.mgrid[0:h, 0:w] + 0.5
    r = 128 + 100 * np.sin(2 * np.pi * x / w) * np.cos(np.pi * y / h)
    g = 128 + 90 * np.cos(2 * np.pi * (x / w + y / h))
    b = 40 + 200 * y / h
    return np.clip(np.rint(np.stack([r, g, b], axis=-1)), 0, 255).astype(np.uint8)


def run_ffmpeg(tmp_path, codes: np.ndarray, opts: str, size) -> np.ndarray:
    src, out = tmp_path / "ff_in.png", tmp_path / "ff_out.png"
    cv2.imwrite(str(src), codes[..., ::-1])
    subprocess.run([ffmpeg(), "-v", "error", "-y", "-i", str(src), "-vf",
                    f"format=gbrp,v360={opts}:interp=line:w={size[0]}:h={size[1]}", "-pix_fmt", "rgb24", str(out)],
                   check=True)
    return cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)


def run_lenslab(tmp_path, codes: np.ndarray, src_spec: str, dst_spec: str, size) -> tuple[np.ndarray, np.ndarray]:
    src, out = tmp_path / "ll_in.exr", tmp_path / "ll_out.exr"
    write(src, codes.astype(np.float32) / 255, pixel_type="float", overwrite=True)
    args = ["warp", str(src), "--from", src_spec, "--to", dst_spec, "--size", f"{size[0]}x{size[1]}",
            "--compat", "v360", "--pixel-type", "float", "-o", str(out), "-q", "--overwrite"]
    assert main(args) == 0
    img = read(out)[0]
    return img[..., :3].astype(np.float64) * 255, img[..., 3]


def fragile(src_spec: str, src_size, dst_spec: str, dst_size) -> np.ndarray:
    """Output pixels whose source sample lies within EDGE px of a face edge or of the source's valid
    region's edge (see EDGE)."""
    src, dst = Camera.from_spec(src_spec, src_size), Camera.from_spec(dst_spec, dst_size)
    w, h = dst_size
    centres = np.stack(np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5), axis=-1)
    xy, ok = exact_map(src, dst, centres)
    out = ~ok
    # the valid region's edge: any point EDGE px away (8 directions) without a ray
    for a in np.arange(8) * np.pi / 4:
        _, near_ok = src.lens.pixel_to_dir(xy + EDGE * np.array([np.cos(a), np.sin(a)]))
        out |= ok & ~near_ok
    lens = src.lens
    if lens.name == "cubemap":
        fw, fh = lens.face_size
        out |= np.abs(xy[..., 0] / fw - np.round(xy[..., 0] / fw)) * fw < EDGE
        out |= np.abs(xy[..., 1] / fh - np.round(xy[..., 1] / fh)) * fh < EDGE
    elif lens.name == "eac":
        fw = lens.width * (1 - 2 * lens.pu) / 3
        fx = (xy[..., 0] - lens.pad) / fw
        out |= np.abs(fx - np.round(fx)) * fw < EDGE
        out |= np.abs(xy[..., 1] - lens.height / 2) < lens.pad + EDGE
    elif lens.name == "dual-fisheye":
        out |= np.abs(xy[..., 0] - lens.width / 2) < EDGE
    return out


def assert_matches_ffmpeg(ours, alpha, theirs, skip):
    keep = (alpha > 0.999) & ~skip
    assert keep.sum() >= 300, keep.sum()  # the comparison really covers the projection
    diff = np.abs(ours - theirs)[keep]
    assert diff.max() <= TOL, (diff.max(), np.argwhere(keep)[np.argmax(diff.max(axis=-1))])


def v360_input(opts: str) -> str:
    name, _, rest = opts.partition(":")
    rest = rest.replace("h_fov", "ih_fov").replace("v_fov", "iv_fov").replace("d_fov", "id_fov")
    return f"input={name}" + (f":{rest}" if rest else "")


def v360_output(opts: str) -> str:
    return "output=" + opts


@pytest.mark.slow
@pytest.mark.parametrize("spec,opts,size", SHARED, ids=[c[1].partition(":")[0] + "-" + c[0] for c in SHARED])
def test_as_output_matches_ffmpeg(tmp_path, spec, opts, size):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg(tmp_path, codes, f"input=e:{v360_output(opts)}", size)
    ours, alpha = run_lenslab(tmp_path, codes, "equirect", spec, size)
    assert_matches_ffmpeg(ours, alpha, theirs, fragile("equirect", (128, 64), spec, size))


@pytest.mark.slow
@pytest.mark.parametrize("spec,opts,size", SHARED, ids=[c[1].partition(":")[0] + "-" + c[0] for c in SHARED])
def test_as_source_matches_ffmpeg(tmp_path, spec, opts, size):
    codes = source_codes(*size)
    theirs = run_ffmpeg(tmp_path, codes, f"{v360_input(opts)}:output=e", (128, 64))
    ours, alpha = run_lenslab(tmp_path, codes, spec, "equirect", (128, 64))
    assert_matches_ffmpeg(ours, alpha, theirs, fragile(spec, size, "equirect", (128, 64)))


def test_little_planet_is_v360_stereographic_looking_down(tmp_path):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg(tmp_path, codes, "input=e:output=sg:h_fov=270:v_fov=270:pitch=-90", (64, 64))
    ours, alpha = run_lenslab(tmp_path, codes, "equirect", "little-planet:fov=270", (64, 64))
    assert_matches_ffmpeg(ours, alpha, theirs, fragile("equirect", (128, 64), "little-planet:fov=270", (64, 64)))


def test_compat_refuses_projections_v360_lacks(tmp_path):
    codes = source_codes(64, 32)
    src, out = tmp_path / "in.exr", tmp_path / "out.exr"
    write(src, codes.astype(np.float32) / 255, overwrite=True)
    for to in ("swirl", "cubemap:layout=4x3", "fisheye:fov=180,cx=0.1"):
        assert main(["warp", str(src), "--to", to, "--size", "64x48", "--compat", "v360", "-o", str(out), "-q"]) == 2  # a usage error, before any file
        assert not out.exists()


@pytest.mark.parametrize("v360_opt,flags", [("yaw=30", ["--yaw", "30"]), ("pitch=20", ["--pitch", "20"]),
                                            ("roll=25", ["--roll", "-25"]),  # v360's roll turns the other way
                                            ("yaw=30:pitch=20:roll=25", ["--yaw", "30", "--pitch", "20", "--roll", "-25"])])
def test_rotations_match_ffmpeg(tmp_path, v360_opt, flags):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg(tmp_path, codes, f"input=e:output=flat:h_fov=90:v_fov=90:{v360_opt}", (64, 64))
    src, out = tmp_path / "in.exr", tmp_path / "out.exr"
    write(src, codes.astype(np.float32) / 255, pixel_type="float")
    assert main(["warp", str(src), "--from", "equirect", "--to", "perspective:fov=90", "--size", "64x64",
                 "--compat", "v360", *flags, "--pixel-type", "float", "-o", str(out), "-q"]) == 0
    ours = read(out)[0]
    assert_matches_ffmpeg(ours[..., :3].astype(np.float64) * 255, ours[..., 3], theirs, np.zeros((64, 64), dtype=bool))
