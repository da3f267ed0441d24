"""The v360 projections lenslab added for ``--compat v360`` (``ball``, Facebook's ``barrel`` and
``barrelsplit``, ``tetrahedron``, ``tsp`` and the ``perspective`` output, lenslab's ``globe``) against
Debian's ffmpeg v360, as the source and as the output (``perspective``: output only in ffmpeg), with the
harness and tolerance of ``tests/warp/test_v360_ffmpeg.py`` (``TOL`` and ``EDGE`` are explained there).

These layouts are made of parts (the barrel's band and caps, the split barrel's halves and quarters)
whose maps jump at their edges; like a cube face's edge there, output pixels whose sample lies within
``EDGE`` px of a part's edge are left out (v360 and lenslab pick the part from float32 and float64 numbers
and both clamp to it)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.maps import exact_map
from tests.warp.test_v360_ffmpeg import EDGE, assert_matches_ffmpeg, fragile, run_ffmpeg, run_lenslab, source_codes

#: (lenslab spec, v360 projection, size, v360 reads it as a source)
NEW = [
    ("ball", "ball", (64, 64), True),
    ("ball", "ball", (96, 64), True),  # each axis spans its own side
    ("fb-barrel", "barrel", (160, 64), True),
    ("fb-barrel", "fb", (200, 80), True),
    ("fb-barrelsplit", "barrelsplit", (96, 64), True),
    ("tetrahedron", "tetrahedron", (64, 64), True),
    ("tsp", "tsp", (128, 64), True),
    ("globe", "perspective", (64, 64), False),  # the defaults: v360 5.1 draws it from 180 radii away
    ("globe:distance=2", "perspective:v_fov=2", (64, 64), False),
    ("globe:distance=0.5", "perspective:v_fov=0.5", (48, 64), False),
]


def part_edges(spec: str, size, dst_spec: str, dst_size) -> np.ndarray:
    """Output pixels whose source sample lies within EDGE px of an edge between two of the source's
    pieces (read from the lens, whatever the model)."""
    src, dst = Camera.from_spec(spec, size), Camera.from_spec(dst_spec, dst_size)
    w, h = dst_size
    centres = np.stack(np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5), axis=-1)
    xy, ok = exact_map(src, dst, centres)
    out = np.zeros((h, w), dtype=bool)
    for p in src.lens.pieces():
        inside = ((xy[..., 0] >= p.x0 - EDGE) & (xy[..., 0] <= p.x0 + p.width + EDGE)
                  & (xy[..., 1] >= p.y0 - EDGE) & (xy[..., 1] <= p.y0 + p.height + EDGE))
        near = (np.minimum.reduce([np.abs(xy[..., 0] - p.x0), np.abs(xy[..., 0] - p.x0 - p.width),
                                   np.abs(xy[..., 1] - p.y0), np.abs(xy[..., 1] - p.y0 - p.height)]) < EDGE)
        out |= ok & inside & near & (len(src.lens.pieces()) > 1)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("spec,v360,size,readable", NEW, ids=[f"{c[1]}-{c[2][0]}x{c[2][1]}" for c in NEW])
def test_as_output_matches_ffmpeg(tmp_path, spec, v360, size, readable):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg(tmp_path, codes, f"input=e:output={v360}", size)
    ours, alpha = run_lenslab(tmp_path, codes, "equirect", spec, size)
    assert_matches_ffmpeg(ours, alpha, theirs, fragile("equirect", (128, 64), spec, size))


SOURCES = [c for c in NEW if c[3]]


@pytest.mark.slow
@pytest.mark.parametrize("spec,v360,size,readable", SOURCES, ids=[f"{c[1]}-{c[2][0]}x{c[2][1]}" for c in SOURCES])
def test_as_source_matches_ffmpeg(tmp_path, spec, v360, size, readable):
    codes = source_codes(*size)
    theirs = run_ffmpeg(tmp_path, codes, f"input={v360}:output=e", (128, 64))
    ours, alpha = run_lenslab(tmp_path, codes, spec, "equirect", (128, 64))
    skip = fragile(spec, size, "equirect", (128, 64)) | part_edges(spec, size, "equirect", (128, 64))
    assert_matches_ffmpeg(ours, alpha, theirs, skip)


def test_globe_is_refused_as_a_v360_source(tmp_path):
    """v360 has no perspective input: with --compat v360 lenslab refuses the globe as a source."""
    from lenslab.cli.main import main
    from lenslab.io import write

    src = tmp_path / "g.exr"
    write(src, source_codes(32, 32).astype(np.float32) / 255)
    assert main(["warp", str(src), "--from", "globe", "--to", "equirect", "--size", "64x32", "--compat", "v360",
                 "-o", str(tmp_path / "o.exr"), "-q"]) == 2  # a usage error, before any file
    assert not (tmp_path / "o.exr").exists()


def test_ball_is_the_equisolid_fisheye_of_the_whole_sphere():
    """On a square frame the ball is ``fisheye:fov=360,mapping=equisolid`` (Lambert's azimuthal
    equal-area projection): the same directions at every pixel."""
    from lenslab.lenses import make_lens

    rng = np.random.default_rng(0)
    xy = rng.random((2000, 2)) * 64
    a, oka = make_lens("ball", (64, 64)).pixel_to_dir(xy)
    b, okb = make_lens("fisheye:fov=360,mapping=equisolid", (64, 64)).pixel_to_dir(xy)
    assert (oka == okb).all()
    np.testing.assert_allclose(a[oka], b[okb], atol=1e-12)
