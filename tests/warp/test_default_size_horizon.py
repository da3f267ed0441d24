"""Without --size, a panorama whose columns are uneven in angle (a cylindrical one, whose rows crowd in angle towards
its top and bottom) keeps the source's resolution along its horizon too, as it did before sizes were measured down
the output's middle column: from a 1024 x 512 equirect (1024 pixels over 360 degrees of longitude), a cylindrical
panorama over 360 degrees has its 1024 columns over the same 360 degrees, and a Facebook barrel its equirect band,
four fifths of the frame's width (ffmpeg's v360 ``barrel`` layout), 1024 wide over 360 degrees. Values from the
layouts' definitions, not from lenslab."""

from __future__ import annotations

import warnings

import pytest

from lenslab.jobs.warp.cameras import default_output_size
from lenslab.lenses.registry import make_lens

SOURCE = make_lens("equirect", (1024, 512))  # 1024 / 360 pixels per degree along every row


@pytest.mark.parametrize("spec", ["cylindrical", "cylindrical:fov=360", "cylindrical-equal-area"])
def test_a_cylindrical_panorama_keeps_the_source_columns_round_its_horizon(spec):
    assert make_lens(spec, (2000, 1000)).fov == 360.0  # (the whole horizon across the width)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # within twice the source's pixels: no note
        w, _ = default_output_size(spec, SOURCE)
    assert w >= 1024


def test_a_facebook_barrel_keeps_the_source_columns_in_its_band():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w, h = default_output_size("fb-barrel", SOURCE)
    assert w * 4 // 5 >= 1024 and w == 5 * h // 2  # the band: 4/5 of a 5:2 frame
