"""A tone curve given as ``--curve`` (the spelling every command accepts beside ``--tone``) is named ``--curve`` in
the usage errors that refuse it (exit 2): with an output that keeps linear light, and with ``--display``. The
spelling expected is the one the test types."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.mark.parametrize("spelling", ["--curve", "--tone"])
@pytest.mark.parametrize("command, extra", [
    ("warp", ["--to", "fisheye", "-o", "{d}/out.exr"]),
    ("convert", ["-o", "{d}/out.exr"]),
    ("warp", ["--to", "fisheye", "-o", "{d}/out.png", "--display", "sRGB"]),
    ("tonemap", ["-o", "{d}/out.png", "--display", "sRGB"]),
])
def test_the_refusal_names_the_option_as_typed(tmp_path, capsys, spelling, command, extra):
    src = tmp_path / "pano.exr"
    write(src, np.full((8, 16, 3), 0.5, np.float32))
    capsys.readouterr()
    assert main([command, str(src), *[e.format(d=tmp_path) for e in extra], spelling, "aces"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lenslab {command}: error: {spelling} "), err
