"""One alpha rule for every command (:func:`lenslab.io.carries_alpha`): where channels have names, the last
of the names the image is written with is ``A``; else 2 or 4 channels. The expected answer is OpenImageIO's
reading of an EXR written with those names (its ``alpha_channel``): a compositor sees alpha exactly where
lenslab does, including an image with one channel more than its input's names (the coverage a warp adds
to ``u, v``), where the look stage and the file reader once disagreed."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio

oiio = pytest.importorskip("OpenImageIO")

CASES = [
    ({"channels": ["u", "v"]}, 3),  # u, v and a warp's coverage: written u, v, A
    ({"channels": ["u", "v"]}, 2),
    ({"channels": ["Y", "A"]}, 2),
    ({"channels": ["Z"]}, 2),
    ({"channels": ["R", "G", "B", "Z"]}, 4),
    ({"channels": ["R", "G", "B"]}, 4),
    ({"channel_names": ["left.R", "left.G", "left.B", "left.A"], "channels": ["R", "G", "B", "A"]}, 4),
    ({"channels": ["Y", "A"]}, 3),  # names that do not fit: R, G, B
    ({}, 4),
    ({}, 3),
    ({}, 2),
]


@pytest.mark.parametrize("meta,count", CASES)
def test_carries_alpha_is_where_openimageio_finds_alpha(tmp_path, meta, count):
    image = np.random.default_rng(count).random((3, 5, count)).astype(np.float32)
    path = tmp_path / "a.exr"
    written = lio.output_channels(meta, count)
    lio.write(path, image, channels=written)
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()  # (OpenImageIO orders the channels its own way: the alpha channel is found by name)
    theirs = spec.alpha_channel >= 0 and spec.channelnames[spec.alpha_channel] == written[-1]
    inp.close()
    assert lio.carries_alpha(meta, count) == theirs


def test_the_look_stage_keeps_a_warps_coverage_beside_two_data_channels():
    from lenslab.io.registry import get
    from lenslab.jobs.stages import Look, develop

    img = np.random.default_rng(1).uniform(0.1, 1, (4, 6, 3)).astype(np.float32)
    out, opts = develop(img.copy(), {"channels": ["u", "v"]}, get("exr"), Look(exposure=1.0))
    # one stop: the data channels times 2 (float64 formula), the coverage untouched
    np.testing.assert_array_equal(out[..., :2], (img[..., :2].astype(np.float64) * 2.0).astype(np.float32))
    np.testing.assert_array_equal(out[..., 2], img[..., 2])
