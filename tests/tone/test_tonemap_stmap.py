"""``lenslab tonemap`` of an ST map that ``lenslab stmap`` wrote (its header's ``lenslab:stmap`` mark) refuses it as
a failed input (exit 1, one line saying how such a map is used), as ``convert`` refuses a look for it: its values
are source positions, which a tone curve would turn into nonsense. In a batch the other files go on; OpenCV reads
the picture written beside it at its own size."""

from __future__ import annotations

import cv2
import numpy as np

import lenslab.io as lio
from lenslab.cli.main import main


def _map(folder):
    path = folder / "st.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "equirect", "--size", "32x16", "-o", str(path),
                 "-q"]) == 0
    return path


def test_tonemap_refuses_an_st_map(tmp_path, capsys):
    st = _map(tmp_path)
    assert main(["tonemap", str(st), "-o", str(tmp_path / "st.png")]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is an ST map" in err and "--stmap" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["st.exr"]


def test_a_batch_goes_on_past_the_map(tmp_path, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    _map(folder)
    lio.write(folder / "pano.exr", np.full((16, 32, 3), 0.5, np.float32))
    assert main(["tonemap", str(folder / "*.exr"), "-o", str(tmp_path / "out"), "--format", "png"]) == 1
    assert "st.exr: is an ST map" in capsys.readouterr().err
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["pano.png"]
    assert cv2.imread(str(tmp_path / "out" / "pano.png")).shape == (16, 32, 3)
