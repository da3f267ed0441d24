"""``--from IMAGE`` of an image that records a mirrored camera (a ``lenslab warp --flip`` output) takes its lens with
that mirror, in ``lenslab warp``, ``lenslab stmap`` and ``lenslab fit points --source``: its lens alone would read the flop's pixels back mirrored, a
world no turn undoes.

Outside values: a flop (``--flip h``, no turn: the recorded camera is the mirror alone) read as its own lens
into that unmirrored lens is each pixel's mirror column, so the ST map holds ``s = 1 - (x + 1/2) / W`` and
``t = 1 - (y + 1/2) / H`` (Nuke's STMap convention, written out here in float64), and the warped pixels are the
flop's read right to left (NumPy's ``[:, ::-1]``)."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from lenslab.io import read, write

W, H = 40, 30
SPEC = "perspective:fov=70"


def _flop(tmp_path):
    """A flop of a 256 x 128 equirect of smooth colour (no two columns alike): ``--flip h``, unturned."""
    y, x = np.mgrid[0:128, 0:256].astype(np.float64)
    img = np.stack([1.5 + np.sin(x / 9.0), 1.5 + np.cos(y / 7.0), 0.2 + (x + 3 * y) / 640.0], axis=-1)
    write(tmp_path / "pano.exr", img.astype(np.float32), pixel_type="float")
    flop = tmp_path / "flop.exr"
    assert main(["warp", str(tmp_path / "pano.exr"), "-o", str(flop), "--to", SPEC, "--size", f"{W}x{H}",
                 "--flip", "h", "--pixel-type", "float", "-q"]) == 0
    assert read(flop)[1]["camera"].pose.mirror == "h"
    return flop


def test_stmap_from_a_flop_reads_each_pixel_from_its_mirror_column(tmp_path):
    flop = _flop(tmp_path)
    out = tmp_path / "map.exr"
    assert main(["stmap", "--from", str(flop), "--to", SPEC, "--size", f"{W}x{H}", "-o", str(out), "-q"]) == 0
    st = read(out)[0]
    y, x = np.mgrid[0:H, 0:W].astype(np.float64) + 0.5
    assert st[..., 3].min() == 1.0
    # float32 coordinates of a perspective lens's projection: a few ulps of 1 (1e-6)
    np.testing.assert_allclose(st[..., 0], 1.0 - x / W, atol=1e-5)
    np.testing.assert_allclose(st[..., 1], 1.0 - y / H, atol=1e-5)


def test_warp_from_a_flop_unmirrors_its_pixels(tmp_path):
    flop = _flop(tmp_path)
    out = tmp_path / "out.exr"
    assert main(["warp", str(flop), "--from", str(flop), "-o", str(out), "--to", SPEC, "--size", f"{W}x{H}",
                 "--pixel-type", "float", "-q"]) == 0
    pixels = read(flop)[0]
    # each output pixel centre reads the mirror pixel centre: bilinear at a centre is that pixel, to float32's rounding
    np.testing.assert_allclose(read(out)[0][..., :3], pixels[:, ::-1, :3], rtol=1e-5, atol=1e-6)


def test_the_repr_of_a_flops_camera_names_its_mirror(tmp_path):
    # a flop of no turn: the recorded camera is the reflection diag(-1, 1, 1) alone (docs/guide/lens-effects.md)
    camera = read(_flop(tmp_path))[1]["camera"]
    np.testing.assert_array_equal(camera.pose.rotation, np.diag([-1.0, 1.0, 1.0]))
    assert repr(camera).startswith(f"Camera(<{SPEC} {W}x{H}>, mirror='h', yaw=0, pitch=0, roll=0")


def test_fit_points_from_a_flop_finds_the_unmirrored_view(tmp_path, capsys):
    # a feature at flop pixel (sx, sy) is at (W - sx, sy) in the unmirrored view of the same lens and pose (the flop
    # is that view read right to left): written out here, the fit must find that lens (fov 70) and no turn
    flop = _flop(tmp_path)
    rows = ["src_x,src_y,x,y"] + [f"{sx},{sy},{W - sx},{sy}" for sx in (3.5, 9.0, 20.0, 27.5, 36.5)
                                  for sy in (2.5, 8.0, 15.0, 22.5, 27.5)]
    csv = tmp_path / "points.csv"
    csv.write_text("\n".join(rows) + "\n")
    assert main(["fit", "points", str(csv), "--model", "perspective", "--size", f"{W}x{H}", "--source", str(flop),
                 "--pose", "--brief"]) == 0
    out = capsys.readouterr().out
    assert "outliers 0" in out
    fov = float(out.split("perspective:fov=")[1].split()[0])
    assert abs(fov - 70.0) < 1e-3  # (nlopt's tolerance on exact points)
