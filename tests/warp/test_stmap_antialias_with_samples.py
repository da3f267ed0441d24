"""``warp --stmap MAP --antialias --samples N``: an ST map warp takes one of the two, and asking both is a
mistake in what was typed: a usage error (exit status 2) in one line before any image is read, not a
failure blamed on each input file (exit 1)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main


def test_antialias_and_samples_with_an_st_map_is_a_usage_error(tmp_path, capsys):
    import lenslab
    from lenslab import Camera
    from lenslab.stmap import st_map, write_st_map

    cam = Camera.from_spec("equirect", (16, 8))
    st = write_st_map(tmp_path / "map.exr", st_map(cam, cam))
    out = tmp_path / "out.exr"
    # the input does not exist: a usage error is said before it would be looked for
    assert main(["warp", str(tmp_path / "no-such.exr"), "--stmap", str(st), "--antialias", "--samples", "4",
                 "-o", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "--antialias or --samples" in lines[0] and "no-such" not in lines[0], lines
    assert not out.exists()
    src = tmp_path / "pano.exr"
    lenslab.write(src, np.ones((8, 16, 3), np.float32))
    assert main(["warp", str(src), "--stmap", str(st), "--samples", "4", "-o", str(out), "-q"]) == 0
