"""``lenslab fit points --source IMAGE`` (an image that records its camera, a flop ``lenslab warp --flip`` wrote) reads
the ``src_x, src_y`` points on that image at its own size when no ``--source-size`` is given: they were read on its
lens stretched to the unknown camera's ``--size`` (a 40 x 40 flop as 64 x 48), and no point fitted (fov 168 degrees,
25 outliers of 25).

Outside values: the points are made here in float64 from the formulas of docs/conventions.md (the pinhole
``u = X / (Z tan(fov/2))``, ``v`` up, pixel centres at +0.5; the flop's camera axes mirrored by ``M = diag(-1, 1, 1)``,
no turn, as ``--source`` takes a flop) for a perspective camera of fov 60 degrees, the value the fit must give
(printed to 6 significant digits; the points are written to 1e-9 px)."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main as lenslab
from lenslab.io import write

W_SRC = H_SRC = 40
FOV_SRC = 90.0
W, H, FOV = 64, 48, 60.0


def _flop(tmp_path):
    y, x = np.mgrid[0:32, 0:64]
    pano = tmp_path / "pano.exr"
    write(pano, np.stack([(x + 0.5) / 64, (y + 0.5) / 32, 0.25 + 0 * x], -1).astype(np.float32), pixel_type="float")
    flop = tmp_path / "flop.exr"
    assert lenslab(["warp", str(pano), "-o", str(flop), "--to", f"perspective:fov={FOV_SRC:g}", "--size",
                    f"{W_SRC}x{H_SRC}", "--yaw", "30", "--flip", "h", "-q"]) == 0
    return flop


def _points(path):
    rng = np.random.default_rng(7)
    xs, ys = rng.uniform(5, 35, 25), rng.uniform(5, 35, 25)
    tan = np.tan(np.radians(FOV_SRC / 2))
    cam = np.stack([(2 * xs / W_SRC - 1) * tan, (1 - 2 * ys / H_SRC) * H_SRC / W_SRC * tan, np.ones(25)], -1)
    d = cam * np.array([-1.0, 1.0, 1.0])  # world = M cam
    t = np.tan(np.radians(FOV / 2))
    u, v = d[:, 0] / d[:, 2] / t, d[:, 1] / d[:, 2] / t
    x, y = (u + 1) * W / 2, (1 - v * W / H) * H / 2
    lines = ["src_x,src_y,x,y"] + [",".join(f"{c:.9f}" for c in row) for row in zip(xs, ys, x, y)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_points_of_a_flop_are_read_at_its_own_size(tmp_path, capsys):
    flop = _flop(tmp_path)
    csv = _points(tmp_path / "pts.csv")
    capsys.readouterr()
    code = lenslab(["fit", "points", str(csv), "--model", "perspective", "--size", f"{W}x{H}", "--source", str(flop)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert f"fitted:   perspective:fov={FOV:g} at {W}x{H}" in out
    assert "points:   25, inliers 25, outliers 0" in out
