"""``lenslab stmap --to render.exr`` without ``--size`` makes the map at the size the render was made at, as ``warp
--to render.exr`` does (the size OpenImageIO reads from the render); the map's warp is the direct warp into that view.
Without --size and without such an image, the size is asked for in one line (exit 2)."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main
from tracer.cli import main as tracer

oiio = pytest.importorskip("OpenImageIO")


def test_the_map_takes_the_renders_size(tmp_path):
    render = tmp_path / "render.exr"
    assert tracer(["render", "--camera", "perspective:fov=60", "--size", "48x32", "--spp", "1", "-o", str(render),
                   "-q"]) == 0
    spec = oiio.ImageInput.open(str(render)).spec()
    size = (spec.width, spec.height)
    assert size == (48, 32)
    st = tmp_path / "st.exr"
    assert main(["stmap", "--from", "equirect", "--source-size", "64x32", "--to", str(render), "-o", str(st),
                 "-q"]) == 0
    m = oiio.ImageBuf(str(st)).spec()
    assert (m.width, m.height) == size
    pano = lio.write(tmp_path / "pano.exr", np.random.default_rng(5).random((32, 64, 3)).astype(np.float32),
                     pixel_type="float")
    outs = []
    for how in (["--stmap", str(st)], ["--to", str(render), "--exact-map"]):  # (both maps exact, in float64)
        out = tmp_path / f"o{len(outs)}.exr"
        assert main(["warp", str(pano), "-o", str(out), *how, "--pixel-type", "float", "-q"]) == 0
        outs.append(oiio.ImageBuf(str(out)).get_pixels(oiio.FLOAT))
    # the map holds each position in float32 (1e-7 of 64 px); the bilinear read moves by the same
    np.testing.assert_allclose(outs[0], outs[1], rtol=0, atol=1e-4)


def test_without_size_nor_render_the_size_is_asked_for(tmp_path, capsys):
    assert main(["stmap", "--from", "equirect", "--to", "fisheye", "-o", str(tmp_path / "st.exr")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--size WxH" in err
    assert not (tmp_path / "st.exr").exists()
