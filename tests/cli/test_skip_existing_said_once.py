"""``--skip-existing`` counts the outputs it left alone once, in the batch's summary line (it was said a
second time before the work began)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.fixture
def two(tmp_path):
    rng = np.random.default_rng(3)
    paths = []
    for i in range(2):
        p = tmp_path / f"in{i}.exr"
        write(p, rng.random((8, 16, 3)).astype(np.float32))
        paths.append(str(p))
    return paths


@pytest.mark.parametrize("command, done", [
    (["convert", "--to", "png"], "converted 1 of 2 file(s) to PNG"),
    (["tonemap", "--format", "png"], "tone-mapped 1 of 2 file(s)"),
    (["warp", "--to", "fisheye:fov=180", "--size", "8x8"], "warped 1 of 2 file(s) with 1 map(s)"),
])
def test_outputs_left_alone_are_counted_once(two, tmp_path, capsys, command, done):
    out = tmp_path / "out"
    assert main([command[0], *two, *command[1:], "-o", str(out)]) == 0
    written = sorted(out.iterdir())
    assert len(written) == 2
    written[1].unlink()  # one left to make again
    capsys.readouterr()
    assert main([command[0], *two, *command[1:], "-o", str(out), "--skip-existing"]) == 0
    err = capsys.readouterr().err
    assert err.count("already there, left alone") == 1, err
    assert f"{done}; 1 already there, left alone" in err, err
    assert written[1].exists()
