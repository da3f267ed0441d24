"""The ``lenslab fit`` command: lens, points and tone, with honest exit statuses."""

from __future__ import annotations

import re

import numpy as np
import pytest

from lenslab import io, tone
from lenslab.cli.main import main
from lenslab.lenses import Camera, make_lens


def test_fit_lens_prints_the_spec_and_residual(capsys):
    code = main(["fit", "lens", "--from", "distortion:k1=-0.03,fov=60", "--model", "brown", "--size", "512x384"])
    out = capsys.readouterr().out
    assert code == 0
    assert re.search(r"fitted:\s+brown:k1=-0\.02", out)
    m = re.search(r"residual: RMS (\S+) px, max (\S+) px at pixel \((\S+), (\S+)\)", out)
    assert m and float(m.group(2)) < 0.05  # half the 1024-px figure at 512 px: well inside 0.05
    assert "BOBYQA" in out and "verdict:  OK" in out


def test_an_impossible_lens_fit_exits_1_and_says_why(capsys):
    code = main(["fit", "lens", "--from", "fisheye:fov=360", "--model", "perspective", "--size", "128x128"])
    cap = capsys.readouterr()
    assert code == 1
    assert "NOT A GOOD FIT" in cap.out and "does not see" in cap.out
    assert cap.err.startswith("lenslab fit lens: error: no good fit")


def test_a_bad_size_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as info:
        main(["fit", "lens", "--from", "perspective", "--model", "fisheye", "--size", "big"])
    assert info.value.code == 2 and "WIDTHxHEIGHT" in capsys.readouterr().err


def test_fit_points_from_a_csv(tmp_path, capsys):
    cam = Camera(make_lens("fisheye:fov=185,mapping=equisolid", (400, 400)))
    rng = np.random.default_rng(2)
    xy = rng.uniform(60, 340, (25, 2))
    _, d, ok = cam.pixel_to_world(xy)
    assert ok.all()
    xy[3] += 40.0  # one mistaken point
    path = tmp_path / "points.csv"
    path.write_text("x,y,dx,dy,dz\n" + "".join(f"{a:.17g},{b:.17g},{p:.17g},{q:.17g},{r:.17g}\n"
                                               for (a, b), (p, q, r) in zip(xy, d)))
    code = main(["fit", "points", str(path), "--model", "fisheye:mapping=equisolid", "--size", "400x400"])
    out = capsys.readouterr().out
    assert code == 0
    m = re.search(r"fitted:\s+fisheye:fov=([\d.]+),mapping=equisolid", out)
    assert m and float(m.group(1)) == pytest.approx(185, abs=1e-6)  # exact points: exact recovery
    assert "outliers 1" in out and out.count("outlier\n") == 1
    assert "line 5" in out.split("outlier\n")[0].splitlines()[-1]  # the fourth data row is on line 5


def test_fit_tone_from_files(tmp_path, capsys):
    rng = np.random.default_rng(4)
    hdr = np.exp(rng.normal(-1.0, 1.5, (48, 64, 3))).astype(np.float32)
    ldr = tone.tonemap(hdr, "hable", 0.5, white=9.0)
    io.write(tmp_path / "scene.exr", hdr, pixel_type="float")
    io.write(tmp_path / "look.png", ldr, bits=16)
    code = main(["fit", "tone", str(tmp_path / "scene.exr"), str(tmp_path / "look.png"), "--curve", "hable"])
    out = capsys.readouterr().out
    assert code == 0
    m = re.search(r"fitted:\s+exposure=(\S+), white=(\S+)", out)
    # a 16-bit PNG of the exact curve: the parameters come back to a thousandth
    assert m and float(m.group(1)) == pytest.approx(0.5, abs=1e-3) and float(m.group(2).rstrip(",")) == pytest.approx(9.0, abs=1e-3)
    before = float(re.search(r"CIEDE2000 before: mean (\S+),", out).group(1))
    after = float(re.search(r"CIEDE2000 after:  mean (\S+),", out).group(1))
    assert after < 0.1 < before


def test_fit_tone_with_a_fixed_parameter(tmp_path, capsys):
    rng = np.random.default_rng(5)
    hdr = np.exp(rng.normal(-1.0, 1.5, (32, 32, 3))).astype(np.float32)
    io.write(tmp_path / "scene.exr", hdr, pixel_type="float")
    io.write(tmp_path / "look.png", tone.tonemap(hdr, "hable", -0.25), bits=16)
    code = main(["fit", "tone", str(tmp_path / "scene.exr"), str(tmp_path / "look.png"), "--param", "white=11.2",
                 "--free", "exposure"])
    out = capsys.readouterr().out
    assert code == 0 and re.search(r"fitted:\s+exposure=-0\.25", out)


@pytest.mark.parametrize("mode", ["fill", "cover"])
def test_warp_autoscale(tmp_path, capsys, mode):
    """``lenslab warp --autoscale``: fill leaves no empty output pixel (alpha 1 everywhere, through the
    warp's own interpolated map); cover shows every source pixel, so the output has an empty margin."""
    io.write(tmp_path / "src.exr", np.ones((120, 160, 3), np.float32), pixel_type="float")
    args = ["warp", str(tmp_path / "src.exr"), "-o", str(tmp_path / "out.exr"), "--from", "barrel:k1=-0.25,fov=90",
            "--to", "perspective:fov=90", "--size", "160x120", "--autoscale"] + ([mode] if mode == "cover" else [])
    assert main(args + ["--verbose"]) == 0
    err = capsys.readouterr().err
    assert f"autoscale {mode}: fov=90 -> fov=" in err  # in the user's terms
    assert "COBYLA check: agrees" in err  # the optimiser's check, with --verbose
    out, meta = io.read(tmp_path / "out.exr")
    fov = meta["camera"].lens.fov
    if mode == "fill":
        assert out.shape[2] == 4 and np.all(out[..., 3] == 1.0)
        assert 95 < fov < 105  # the barrel lens sees more than its nominal 90 deg (see test_fit_autoscale)
    else:
        assert np.any(out[..., 3] == 0.0) and fov > 110
