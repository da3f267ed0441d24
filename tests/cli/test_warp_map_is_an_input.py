"""``lenslab warp --stmap MAP``: the map is an input of the command as much as the image is. Named as the output
(by the same name, another spelling of it, or a link), it is a usage error (exit status 2, as the brief gives
usage errors) and the map's bytes stay as they were, even with ``--overwrite``; in one file and in a batch."""

from __future__ import annotations

import os

import numpy as np
import pytest

from tests.cli_entry_points import all_commands, run


@pytest.fixture()
def work(tmp_path):
    from lenslab.io import write

    rng = np.random.default_rng(3)
    write(tmp_path / "pano.exr", rng.uniform(0.0, 2.0, (16, 32, 3)).astype(np.float32))
    st = np.zeros((8, 8, 3), np.float32)  # an ST map: R = x / W, G = 1 - y / H of the source position
    st[..., 0], st[..., 1] = np.meshgrid((np.arange(8) + 0.5) / 8, 1 - (np.arange(8) + 0.5) / 8)
    write(tmp_path / "map.exr", st)
    (tmp_path / "batch").mkdir()
    write(tmp_path / "batch" / "a.exr", rng.uniform(0.0, 2.0, (16, 32, 3)).astype(np.float32))
    return tmp_path


def _warp():
    return next(c for c in all_commands() if c.name == "lenslab warp")


@pytest.mark.parametrize("form", ["same name", "absolute name", "symbolic link", "hard link"])
def test_the_map_named_as_the_output_is_a_usage_error(work, form):
    stmap, before = work / "map.exr", (work / "map.exr").read_bytes()
    out = {"same name": stmap, "absolute name": stmap.absolute()}.get(form, work / "other.exr")
    if form == "symbolic link":
        os.symlink(stmap, out)
    elif form == "hard link":
        os.link(stmap, out)
    code, _, err = run(_warp(), [str(work / "pano.exr"), "--stmap", os.path.relpath(stmap), "-o", str(out),
                                 "--overwrite"])
    assert code == 2, err
    assert err.strip().splitlines() == [f"lenslab warp: error: {out}: is an input of this command; it is never "
                                        "written over, even with --overwrite: choose another output name"], err
    assert stmap.read_bytes() == before


def test_a_batch_whose_output_is_the_map_is_a_usage_error(work):
    """The map lies in the output folder under the name a warped input would take."""
    (work / "out").mkdir()
    os.replace(work / "map.exr", work / "out" / "a.exr")
    stmap, before = work / "out" / "a.exr", (work / "out" / "a.exr").read_bytes()
    code, _, err = run(_warp(), [str(work / "batch"), "--stmap", str(stmap), "-o", str(work / "out"),
                                 "--format", "exr", "--overwrite"])
    assert code == 2, err
    assert "is an input of this command" in err and len(err.strip().splitlines()) == 1, err
    assert stmap.read_bytes() == before
