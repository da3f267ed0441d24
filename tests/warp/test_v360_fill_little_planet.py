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


@pytest.mark.parametrize("fov", [270, 200])
def test_a_little_planet_source_is_read_as_v360_reads_sg_looking_down(tmp_path, fov):
    """As a source, v360's ``sg`` seen looking down (``input=sg``, ``pitch=90`` turning the output's rays onto it)
    reads the whole frame, corners included, and the input's top-left pixel for what it does not see: every
    output pixel drawn. Compared at every pixel but a band along the edge of what the source sees."""
    import numpy as np

    from tests.warp.test_v360_ffmpeg import TOL
    from tests.warp.test_v360_fill import seen_edge

    spec, size = f"little-planet:fov={fov}", (64, 64)
    codes = source_codes(*size)
    theirs = run_ffmpeg_rgba(tmp_path, codes, f"input=sg:ih_fov={fov}:iv_fov={fov}:pitch=90:output=e", (128, 64))
    ours = run_lenslab(tmp_path, codes, "equirect", (128, 64), source=spec)
    keep = ~seen_edge(spec, size)
    assert keep.mean() > 0.8, keep.mean()
    diff = np.abs(ours[..., :3] - theirs[..., :3]).max(axis=-1)[keep]
    assert diff.max() <= TOL, (diff.max(), np.argwhere(keep)[np.argmax(diff)])
    np.testing.assert_array_equal(ours[..., 3], 1.0)  # every pixel drawn, as v360 draws every pixel
    np.testing.assert_array_equal(theirs[..., 3], 255)
