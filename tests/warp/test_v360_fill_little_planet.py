"""``lenslab warp --to little-planet --compat v360`` fills the frame's corners as ffmpeg's v360 does for the
same view (``output=sg`` with ``pitch=-90``, docs/v360.md): the stereographic formula carried on past the
field of view. Before, the corners (a fifth of a square frame at the default 270 degrees) were left
transparent, while ``--to fisheye:mapping=stereographic --pitch -90`` filled them. Expected values: Debian's
ffmpeg on the same opaque source, every pixel but those on a jump of v360's map (tests.warp.test_v360_fill)."""

from __future__ import annotations

import pytest

from tests.warp.test_v360_fill import assert_fills_as_ffmpeg, jumps, run_ffmpeg_rgba, run_lenslab
from tests.warp.test_v360_ffmpeg import source_codes


@pytest.mark.parametrize("fov", [270, 200])
def test_little_planet_corners_are_filled_as_v360_sg_looking_down(tmp_path, fov):
    codes = source_codes(128, 64)
    theirs = run_ffmpeg_rgba(tmp_path, codes, f"input=e:output=sg:h_fov={fov}:v_fov={fov}:pitch=-90", (64, 64))
    assert (theirs[..., 3] == 255).all()  # v360 fills every pixel, the corners included
    ours = run_lenslab(tmp_path, codes, f"little-planet:fov={fov}", (64, 64))
    assert_fills_as_ffmpeg(ours, theirs, jumps(f"little-planet:fov={fov}", (64, 64)))
