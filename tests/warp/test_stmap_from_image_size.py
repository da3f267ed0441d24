"""``lenslab stmap --from IMAGE`` (an image that records its camera, a flop ``lenslab warp --flip`` wrote) maps onto
that image as it is, its own size, when no ``--source-size`` is given: the map was made for a source of the map's
``--size`` (a 40 x 40 flop read as 64 x 32, its lens stretched), which a compositor applies to the plate without a word.

Outside values: the flop's size as OpenImageIO reads it, and each map pixel's source position from the formulas of
docs/conventions.md transcribed here in float64 (the equirect's direction of a pixel centre; the camera axes mirrored
by ``M = diag(-1, 1, 1)``, no turn, as ``--from`` takes a flop; the pinhole ``u = X / (Z tan(fov/2))``; Nuke's
``s = x / W``, ``t = 1 - y / H``). Tolerance 1e-4 of the frame: the map is float32 (7 digits of 1.0)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import read, write

oiio = pytest.importorskip("OpenImageIO")

W_OUT, H_OUT = 64, 32
FOV = 90.0


def _flop(tmp_path):
    h, w = 32, 64
    y, x = np.mgrid[0:h, 0:w]
    pano = tmp_path / "pano.exr"
    write(pano, np.stack([(x + 0.5) / w, (y + 0.5) / h, 0.25 + 0 * x], -1).astype(np.float32), pixel_type="float")
    flop = tmp_path / "flop.exr"
    assert lenslab(["warp", str(pano), "-o", str(flop), "--to", f"perspective:fov={FOV:g}", "--size", "40x40",
                    "--yaw", "30", "--flip", "h", "-q"]) == 0
    return flop


def _expected_st(w_src, h_src):
    """Nuke's (s, t) of each output pixel centre of a W_OUT x H_OUT equirect seen by the unturned, mirrored pinhole."""
    y, x = np.mgrid[0:H_OUT, 0:W_OUT].astype(np.float64) + 0.5
    lon = np.radians((2 * x / W_OUT - 1) * 180.0)
    lat = np.radians((1 - 2 * y / H_OUT) * 90.0)
    d = np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], -1)
    cam = d * np.array([-1.0, 1.0, 1.0])  # R^T d with R = M = diag(-1, 1, 1)
    tan = np.tan(np.radians(FOV / 2))
    with np.errstate(divide="ignore", invalid="ignore"):
        u = cam[..., 0] / (cam[..., 2] * tan)
        v = cam[..., 1] / (cam[..., 2] * tan)
    xs = (u + 1) * w_src / 2
    ys = (1 - v * w_src / h_src) * h_src / 2
    seen = (cam[..., 2] > 0) & (xs > 0) & (xs < w_src) & (ys > 0) & (ys < h_src)
    return xs / w_src, 1 - ys / h_src, seen


def test_a_map_from_an_image_is_made_for_that_image(tmp_path, capsys):
    flop = _flop(tmp_path)
    spec = oiio.ImageInput.open(str(flop)).spec()
    w_src, h_src = spec.width, spec.height
    assert (w_src, h_src) == (40, 40)
    out = tmp_path / "map.exr"
    assert lenslab(["stmap", "-o", str(out), "--from", str(flop), "--to", "equirect", "--size",
                    f"{W_OUT}x{H_OUT}", "-q"]) == 0
    st, meta = read(out)
    s, t, seen = _expected_st(w_src, h_src)
    inner = seen & (st[..., 3] == 1)  # (pixels whose footprint crosses the frame's edge aside)
    assert inner.sum() > 0.8 * seen.sum()
    assert np.abs(st[..., 0][inner] - s[inner]).max() < 1e-4
    assert np.abs(st[..., 1][inner] - t[inner]).max() < 1e-4
    warped = tmp_path / "warped.exr"  # the map applies to the flop itself, as its mark says
    capsys.readouterr()
    assert lenslab(["warp", str(flop), "-o", str(warped), "--stmap", str(out), "-q"]) == 0, capsys.readouterr().err
