"""A remap grid normalised as OpenCV counts rows (``G = y / H``, growing down the image) looks like an ST map, but
``--stmap`` reads G as Nuke's ``t = 1 - y / H``: ``lenslab info`` says the warp by it would come out upside down and
how to mend it. What OpenCV's ``remap`` makes of the grid is the reference: lenslab's nearest-pixel warp by the
mended map (``1 - G``) is it, by the grid as written it is not."""

from __future__ import annotations

import cv2
import numpy as np

import lenslab.io as lio
from lenslab.cli.main import main

W, H = 80, 60


def _grid():
    k = np.array([[60.0, 0, 40], [0, 60, 30], [0, 0, 1]])
    return cv2.initUndistortRectifyMap(k, np.array([-0.3, 0.1, 0, 0]), None, k, (W, H), cv2.CV_32FC1)


def _write_map(path, g):
    mx, _ = _grid()
    assert cv2.imwrite(str(path), np.dstack([np.zeros_like(mx), g, (mx + 0.5) / W]).astype(np.float32))  # B, G, R


def test_info_says_a_grid_growing_down_would_warp_upside_down(tmp_path, capsys):
    mx, my = _grid()
    down, mended = tmp_path / "down.tiff", tmp_path / "mended.tiff"
    _write_map(down, (my + 0.5) / H)
    _write_map(mended, 1 - (my + 0.5) / H)
    assert main(["info", str(down)]) == 0
    out = capsys.readouterr().out
    assert "grows down the image" in out and "upside down" in out and "store 1 - G" in out, out
    assert "give --stmap" not in out
    assert main(["info", str(mended)]) == 0
    assert f"give --stmap {mended}" in capsys.readouterr().out

    rng = np.random.default_rng(7)
    src = rng.random((H, W, 3)).astype(np.float32)
    lio.write(tmp_path / "src.exr", src)
    reference = cv2.remap(src, mx, my, cv2.INTER_NEAREST)  # OpenCV's warp by its own grid
    inside = (mx >= 0) & (mx <= W - 1) & (my >= 0) & (my <= H - 1)
    agree = {}
    for m in (down, mended):
        out_path = tmp_path / f"out-{m.stem}.exr"
        assert main(["warp", str(tmp_path / "src.exr"), "--stmap", str(m), "-o", str(out_path), "--filter", "nearest",
                     "--pixel-type", "float", "-q"]) == 0
        warped = lio.read(out_path)[0][..., :3]
        # the source is stored as half floats: values in [0, 1) to 2^-12 of their own (0.000244 at most)
        agree[m.stem] = np.all(np.abs(warped - reference) <= 2.0 ** -12, axis=-1)[inside].mean()
    # the mended map reads OpenCV's pixels (a tie between two centres may go the other way); as written, it reads
    # the rows mirrored
    assert agree["mended"] > 0.99 and agree["down"] < 0.2, agree
