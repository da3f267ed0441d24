"""``lenslab warp --help`` says what size a warp without ``--size`` makes, and it is the size made: the
source's angular resolution (an equirect's rows over 180 degrees) in the output lens's own shape (a square
fisheye, a 2:1 equirect, a 3:2 cube map of square faces), each eye of a stereo frame at that height."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main


def test_help_names_the_shapes(capsys):
    with pytest.raises(SystemExit):
        main(["warp", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "default: the source's angular resolution in the output lens's own shape" in text
    assert "3:2 for a 3x2 cube map" in text


@pytest.mark.parametrize("to, size", [
    ("fisheye:fov=180", (32, 32)),
    ("equirect", (64, 32)),
    ("cubemap", (48, 32)),  # 3 x 2 faces of 16 x 16 pixels
    ("stereo:tb,base=half-equirect", (32, 64)),  # two eyes of 32 rows
])
def test_default_size_is_what_help_says(tmp_path, to, size):
    import lenslab

    src = tmp_path / "pano.exr"
    lenslab.write(src, np.ones((32, 64, 3), np.float32))
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "--to", to, "-o", str(out), "-q"]) == 0
    assert tuple(lenslab.read(out)[1]["size"]) == size
