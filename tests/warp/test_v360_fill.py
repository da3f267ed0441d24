"""``lenslab warp --compat v360`` fills the output pixels ffmpeg's v360 fills, with what v360 puts there.

v360 (its default ``alpha_mask=0``) writes every output pixel: past a fisheye's circle, outside a Hammer
ellipse or a sinusoidal frame's sine curves and in an EAC frame's padding its formulas carry on; at the
pixels it reports invisible (``ball`` and ``perspective`` off the circle, ``og`` past 90 degrees) it samples
down or forward; an equisolid frame past the back pole is left at zero. Debian's ffmpeg converts an opaque
RGBA source (``format=gbrap``): its output's alpha says which pixels it filled from the source (255) and
which it left at zero, and lenslab's colour and alpha are compared with it at every pixel of the frame,
corners included.

As its source, v360 reads a direction its input projection does not see from the input's top-left pixel
(``flat``, fisheye, ``cylindrical``, ``pannini``), and its fisheye inputs see their whole frame, corners
included; ``mercator`` and ``hequirect`` clamp to their edges: those too are compared at every pixel but for
a band along the edge of what the source sees, where v360 decides from float32 numbers and, at the frame's
edge, by its own rounding.
"""

from __future__ import annotations

import subprocess

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera
from lenslab.warp.compat_v360 import v360_output
from lenslab.warp.maps import exact_map_parts

from tests.warp.test_v360_ffmpeg import EDGE, SHARED, TOL, ffmpeg, source_codes, v360_input

#: a pixel centre this close (px) to a jump in v360's map (the edge of a fill, a face or a half) is left
#: out: v360 decides its side in float32, lenslab in float64; a smooth map moves 1e-4 radians over it
JUMP = 1e-3

#: (lenslab spec, v360 output with its options, size, extra v360 options, lenslab flags)
CASES = [
    ("fisheye:fov=180", "fisheye:h_fov=180:v_fov=180", (64, 64)),
    ("fisheye:fov=300", "fisheye:h_fov=300:v_fov=300", (64, 64)),  # corners past the back pole
    ("fisheye:fov=180,mapping=stereographic", "sg:h_fov=180:v_fov=180", (64, 64)),
    ("fisheye:fov=200,mapping=equisolid", "equisolid:h_fov=200:v_fov=200", (64, 64)),  # zeros past the back pole
    ("fisheye:fov=160,mapping=orthographic", "og:h_fov=160:v_fov=160", (64, 64)),  # forward past 90 degrees
    ("eac:pad=2", "eac", (96, 64)),
    ("dual-fisheye:fov=190,front=right", "dfisheye:h_fov=190:v_fov=190", (128, 64)),
    ("hammer", "hammer", (128, 64)),
    ("sinusoidal", "sinusoidal", (128, 64)),
    ("ball", "ball", (64, 64)),  # down off the circle
    ("globe:distance=2", "perspective:v_fov=2", (64, 64)),  # down off the sphere
]
#: the directions sampled at invisible pixels turn with the view
TURNED = [(spec, opts, size) for spec, opts, size in CASES if spec.startswith(("ball", "globe", "fisheye:fov=160", "fisheye:fov=300"))]


def run_ffmpeg_rgba(tmp_path, codes: np.ndarray, opts: str, size) -> np.ndarray:
    src, out = tmp_path / "ff_in.png", tmp_path / "ff_out.png"
    cv2.imwrite(str(src), np.dstack([codes[..., ::-1], np.full(codes.shape[:2], 255, np.uint8)]))
    subprocess.run([ffmpeg(), "-v", "error", "-y", "-i", str(src), "-vf",
                    f"format=gbrap,v360={opts}:interp=line:w={size[0]}:h={size[1]}", "-pix_fmt", "rgba", str(out)],
                   check=True)
    return cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., [2, 1, 0, 3]].astype(np.float64)


def run_lenslab(tmp_path, codes, spec, size, flags=(), compat=True, source="equirect") -> np.ndarray:
    src, out = tmp_path / "ll_in.exr", tmp_path / "ll_out.exr"
    write(src, codes.astype(np.float32) / 255, pixel_type="float", overwrite=True)
    args = ["warp", str(src), "--from", source, "--to", spec, "--size", f"{size[0]}x{size[1]}", *flags,
            "--pixel-type", "float", "-o", str(out), "-q", "--overwrite"] + (["--compat", "v360"] if compat else [])
    assert main(args) == 0
    img = read(out)[0].astype(np.float64)
    return np.dstack([img[..., :3] * 255, img[..., 3:4]])


def jumps(spec: str, size, yaw: float = 0.0, pitch: float = 0.0) -> np.ndarray:
    """Output pixels whose centre lies within JUMP px of a jump in v360's map (see JUMP)."""
    cam = v360_output(Camera.from_spec(spec, size, yaw=yaw, pitch=pitch))
    w, h = size
    centres = np.stack(np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5), axis=-1)
    d0, ok0 = cam.lens.pixel_to_dir(centres)
    out = np.zeros((h, w), dtype=bool)
    for step in ((JUMP, 0), (-JUMP, 0), (0, JUMP), (0, -JUMP)):
        d, ok = cam.lens.pixel_to_dir(centres + step)
        out |= (ok != ok0) | (ok & ok0 & (np.einsum("...i,...i->...", d, d0) < np.cos(0.05)))
    return out


def assert_fills_as_ffmpeg(ours, theirs, skip):
    keep = ~skip
    assert keep.mean() > 0.95, keep.mean()  # the whole frame is compared but for a few pixels on jumps
    diff = np.abs(ours[..., :3] - theirs[..., :3]).max(axis=-1)[keep]
    assert diff.max() <= TOL, (diff.max(), np.argwhere(keep)[np.argmax(diff)])
    # alpha: 1 where v360 filled the pixel from the (opaque) source, 0 where it wrote zeros
    np.testing.assert_array_equal(ours[..., 3][keep], theirs[..., 3][keep] / 255)


@pytest.mark.slow
@pytest.mark.parametrize("spec,opts,size", CASES, ids=[c[0] for c in CASES])
def test_compat_fills_what_v360_fills(tmp_path, spec, opts, size):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg_rgba(tmp_path, codes, f"input=e:output={opts}", size)
    ours = run_lenslab(tmp_path, codes, spec, size)
    assert_fills_as_ffmpeg(ours, theirs, jumps(spec, size))


@pytest.mark.slow
@pytest.mark.parametrize("spec,opts,size", TURNED, ids=[c[0] for c in TURNED])
def test_filled_directions_turn_with_the_view(tmp_path, spec, opts, size):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg_rgba(tmp_path, codes, f"input=e:output={opts}:yaw=40:pitch=30", size)
    ours = run_lenslab(tmp_path, codes, spec, size, ["--yaw", "40", "--pitch", "30"])
    assert_fills_as_ffmpeg(ours, theirs, jumps(spec, size, 40.0, 30.0))


def test_stereo_output_fills_each_eye(tmp_path):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg_rgba(tmp_path, codes, "input=e:output=fisheye:h_fov=200:v_fov=200:out_stereo=sbs", (64, 64))
    ours = run_lenslab(tmp_path, codes, "stereo:sbs,base=fisheye,fov=200", (128, 64))
    eye = jumps("fisheye:fov=200", (64, 64))
    assert_fills_as_ffmpeg(ours, theirs, np.hstack([eye, eye]))


def test_without_compat_the_corners_have_no_ray(tmp_path):
    codes = source_codes(128, 64)
    ours = run_lenslab(tmp_path, codes, "fisheye:fov=180", (64, 64), compat=False)
    y, x = np.mgrid[0:64, 0:64] + 0.5
    r = np.hypot(x - 32, y - 32) / 32  # the image circle touches the frame's sides
    outside, inside = r > 1 + 1 / 32, r < 1 - 1 / 32  # a pixel's width from the rim: no partial coverage
    assert outside.sum() > 700 and np.all(ours[outside] == 0)  # transparent black: no ray
    assert np.all(ours[..., 3][inside] == 1)


#: sources with directions they do not see (the others cover the whole sphere)
PARTIAL = [case for case in SHARED if case[0].startswith(("half-equirect", "perspective", "fisheye", "cylindrical:",
                                                          "mercator", "pannini"))]


def seen_edge(spec: str, size, out_size=(128, 64)) -> np.ndarray:
    """Output pixels within EDGE output pixels (8 directions) of one whose ray the source sees differently,
    by lenslab's lens or by where it says v360 still reads (``v360_dir_to_pixel``)."""
    src, dst = Camera.from_spec(spec, size), Camera.from_spec("equirect", out_size)
    w, h = out_size
    centres = np.stack(np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5), axis=-1)

    def seen(pts):
        _, ok, _, d = exact_map_parts(src, dst, pts, with_dirs=True)
        further = getattr(src.lens, "v360_dir_to_pixel", None)
        return ok | (further(d)[1] if further is not None else False)

    at = seen(centres)
    out = np.zeros((h, w), dtype=bool)
    for a in np.arange(8) * np.pi / 4:
        out |= seen(centres + EDGE * np.array([np.cos(a), np.sin(a)])) != at
    return out


@pytest.mark.slow
@pytest.mark.parametrize("spec,opts,size", PARTIAL, ids=[c[0] for c in PARTIAL])
def test_what_the_source_does_not_see_is_read_as_v360_reads_it(tmp_path, spec, opts, size):
    codes = source_codes(*size)
    theirs = run_ffmpeg_rgba(tmp_path, codes, f"{v360_input(opts)}:output=e", (128, 64))
    ours = run_lenslab(tmp_path, codes, "equirect", (128, 64), source=spec)
    skip = seen_edge(spec, size)
    keep = ~skip
    assert keep.mean() > 0.8, keep.mean()
    diff = np.abs(ours[..., :3] - theirs[..., :3]).max(axis=-1)[keep]
    assert diff.max() <= TOL, (diff.max(), np.argwhere(keep)[np.argmax(diff)])
    np.testing.assert_array_equal(ours[..., 3], 1.0)  # every pixel drawn, as v360 draws every pixel
    np.testing.assert_array_equal(theirs[..., 3], 255)
