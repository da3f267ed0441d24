"""``lenslab stmap --from IMAGE`` makes the map for that image at its own size (``--size`` is the output's), so the
map applies to the image; ``--source-size`` still says another size.

Outside value: the map of a flop (``--flip h`` of a 40x30 ``perspective:fov=70``) into a 96x48 equirect holds, at
each output pixel centre, the pinhole projection of the equirect ray mirrored in x, written out here in float64:
``d = (cos(lat) sin(lon), sin(lat), cos(lat) cos(lon))``, ``u = W/2 - f d_x / d_z``, ``v = H/2 - f d_y / d_z`` with
``f = (W/2) / tan(35 deg)``, as ``s = u / W`` and ``t = 1 - v / H`` (Nuke's STMap convention)."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from lenslab.io import read
from tests.warp.test_from_mirrored_image import H, SPEC, W, _flop  # a 40x30 perspective:fov=70 flop (--flip h)

OW, OH = 96, 48
assert SPEC == "perspective:fov=70"  # the f of the formula above


def test_stmap_from_an_image_reads_it_at_its_own_size(tmp_path):
    flop = _flop(tmp_path)
    st_file = tmp_path / "map.exr"
    assert main(["stmap", "--from", str(flop), "--to", "equirect", "--size", f"{OW}x{OH}", "-o", str(st_file),
                 "-q"]) == 0
    st = read(st_file)[0]
    assert st.shape[:2] == (OH, OW)
    y, x = np.mgrid[0:OH, 0:OW].astype(np.float64) + 0.5
    lon, lat = (x / OW - 0.5) * 2 * np.pi, (0.5 - y / OH) * np.pi
    d = np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], axis=-1)
    f = (W / 2) / np.tan(np.radians(35.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        u, v = W / 2 - f * d[..., 0] / d[..., 2], H / 2 - f * d[..., 1] / d[..., 2]
    seen = (d[..., 2] > 0) & (u > 0) & (u < W) & (v > 0) & (v < H)
    inner = (d[..., 2] > 0) & (u > 0.5) & (u < W - 0.5) & (v > 0.5) & (v < H - 0.5)
    alpha = st[..., 3] > 0
    assert alpha[inner].all() and not alpha[~seen].any()
    # the map is stored as float32: 1e-6 of s and t in [0, 1], with margin for the ray's float64 -> float32 steps
    np.testing.assert_allclose(st[..., 0][inner], u[inner] / W, atol=1e-5)
    np.testing.assert_allclose(st[..., 1][inner], 1 - v[inner] / H, atol=1e-5)
    # the map applies to the image it was made from: as the lens-to-lens warp of the same cameras
    applied, direct = tmp_path / "applied.exr", tmp_path / "direct.exr"
    assert main(["warp", str(flop), "--stmap", str(st_file), "-o", str(applied), "--pixel-type", "float", "-q"]) == 0
    assert main(["warp", str(flop), "--from", str(flop), "--to", "equirect", "--size", f"{OW}x{OH}", "-o",
                 str(direct), "--pixel-type", "float", "-q"]) == 0
    np.testing.assert_allclose(read(applied)[0], read(direct)[0], rtol=1e-5, atol=1e-6)


def test_source_size_still_says_another_size(tmp_path):
    flop = _flop(tmp_path)
    st_file = tmp_path / "map.exr"
    assert main(["stmap", "--from", str(flop), "--source-size", f"{2 * W}x{2 * H}", "--to", "equirect", "--size",
                 f"{OW}x{OH}", "-o", str(st_file), "-q"]) == 0
    assert f"{2 * W}x{2 * H}" in read(st_file)[1]["attributes"]["lenslab:stmap"]
