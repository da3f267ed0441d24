"""The ``info`` and ``convert`` commands on a directory of mixed files, one of them corrupt."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main


@pytest.fixture
def mixed(tmp_path):
    d = tmp_path / "in"
    d.mkdir()
    rng = np.random.default_rng(0)
    hdr = (rng.random((12, 16, 3)) * 4).astype(np.float32)
    hdr[0, 0] = [np.nan, np.inf, -1.0]
    from lenslab.lenses import Camera

    cam = Camera.from_spec("perspective:fov=60", (16, 12))
    lio.write(d / "a.exr", hdr, camera=cam)
    lio.write(d / "b.pfm", np.abs(np.nan_to_num(hdr, nan=0, posinf=0, neginf=0)))
    lio.write(d / "c.png", rng.random((12, 16, 3)).astype(np.float32))
    lio.write(d / "d.jpg", rng.random((12, 16, 3)).astype(np.float32))
    lio.write(d / "e.pgm", rng.random((12, 16, 1)).astype(np.float32), bits=16)
    (d / "z_corrupt.exr").write_bytes((d / "a.exr").read_bytes()[:200])
    (d / "readme.txt").write_text("not an image")  # not an image extension: ignored in a directory
    return d


def test_info_text_and_json(mixed, capsys):
    rc = main(["info", str(mixed / "a.exr"), str(mixed / "c.png")])
    out = capsys.readouterr().out
    assert rc == 0
    assert "EXR 16 x 12" in out and "lens: perspective:fov=60" in out and "PNG 16 x 12" in out
    rc = main(["info", "--json", str(mixed / "a.exr"), str(mixed / "z_corrupt.exr")])
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert rc == 1 and "z_corrupt.exr" in captured.err
    a = data[0]
    assert a["format"] == "exr" and a["width"] == 16 and a["height"] == 12 and a["lens"].startswith("perspective")
    r, g, b = a["stats"]
    assert (r["nan"], g["inf"], b["negative"]) == (1, 1, 1)
    img, _ = lio.read(mixed / "a.exr")
    assert r["max"] == pytest.approx(float(np.nanmax(img[..., 0])))  # finite values only
    assert g["mean"] == pytest.approx(float(img[..., 1][np.isfinite(img[..., 1])].mean()), rel=1e-6)
    assert "error" in data[1] and "z_corrupt.exr" in data[1]["error"]


def test_convert_directory_with_a_corrupt_file(mixed, tmp_path, capsys):
    out = tmp_path / "out"
    rc = main(["convert", str(mixed), "--to", "jpg", "-o", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 1  # one input failed
    assert "z_corrupt.exr" in err and ": error: " in err
    assert "note: " in err and "a.exr" in err  # a.exr's NaN, inf and negative repairs are reported
    assert sorted(os.listdir(out)) == ["a.jpg", "b.jpg", "c.jpg", "d.jpg", "e.jpg"]  # nothing partial
    img, meta = lio.read(out / "a.jpg")
    assert meta["format"] == "jpg" and img.shape == (12, 16, 3)
    # LDR -> LDR keeps the picture (no tone curve): PNG codes survive within JPG error
    png, _ = lio.read(mixed / "c.png", raw=True)
    jpg, _ = lio.read(out / "c.jpg", raw=True)
    assert np.abs(png - jpg).mean() < 0.03  # random noise at quality 95: a few codes on average

    # again: every existing output is refused without --overwrite, and left untouched
    before = {p: (out / p).read_bytes() for p in os.listdir(out)}
    rc = main(["convert", str(mixed / "a.exr"), str(mixed / "b.pfm"), "--to", "jpg", "-o", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 1 and err.count("already exists") == 2
    assert {p: (out / p).read_bytes() for p in os.listdir(out)} == before
    rc = main(["convert", str(mixed / "a.exr"), "--to", "jpg", "-o", str(out), "--overwrite", "--exposure", "-2",
               "--quiet"])
    assert rc == 0 and (out / "a.jpg").read_bytes() != before["a.jpg"]


def test_convert_hdr_formats_keep_values_and_camera(mixed, tmp_path):
    out = tmp_path / "o"
    rc = main(["convert", str(mixed / "b.pfm"), str(mixed / "a.exr"), "--to", "exr", "-o", str(out),
               "--pixel-type", "float", "--quiet"])
    assert rc == 0
    src, _ = lio.read(mixed / "b.pfm")
    back, _ = lio.read(out / "b.exr")
    np.testing.assert_array_equal(back, src)
    _, meta = lio.read(out / "a.exr")
    assert meta["camera"] is not None and meta["camera"].lens.spec().startswith("perspective")
    rc = main(["convert", str(mixed / "a.exr"), "--to", "pfm", "-o", str(out / "single.pfm"), "--quiet"])
    assert rc == 0 and (out / "single.pfm").exists()


def test_convert_globs_jobs_and_tone(mixed, tmp_path):
    out = tmp_path / "g"
    rc = main(["convert", str(mixed / "*.exr"), str(mixed / "b.pfm"), "--to", "png", "-o", str(out),
               "--jobs", "2", "--tone", "clamp", "--quiet"])
    assert rc == 1  # the corrupt EXR matched the glob too
    assert sorted(os.listdir(out)) == ["a.png", "b.png"]
    png, _ = lio.read(out / "b.png")
    src, _ = lio.read(mixed / "b.pfm")
    from lenslab.io.encode import decode_srgb, encode_quantise
    from lenslab.tone import tonemap

    expect = decode_srgb(encode_quantise(tonemap(src, curve="clamp", exposure=0.0)), 255)  # b.pfm has no NaN
    np.testing.assert_array_equal(png, expect)  # HDR -> LDR: the tone curve, then sRGB, nothing else


def test_convert_output_file_needs_one_input(mixed, tmp_path, capsys):
    rc = main(["convert", str(mixed / "a.exr"), str(mixed / "b.pfm"), "--to", "jpg", "-o", str(tmp_path / "x.jpg")])
    assert rc == 2 and "names a file" in capsys.readouterr().err and not (tmp_path / "x.jpg").exists()


def test_convert_reports_missing_inputs(tmp_path, capsys):
    rc = main(["convert", str(tmp_path / "nothing*.exr"), str(tmp_path / "missing.exr"), "--to", "png", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 1 and "matches no file" in err and "missing.exr" in err


def test_command_line_entry_point(mixed):
    res = subprocess.run([sys.executable, "-m", "lenslab", "info", str(mixed / "e.pgm")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and "PGM 16 x 12" in res.stdout and "uint 16-bit" in res.stdout
    res = subprocess.run([sys.executable, "-m", "lenslab", "info", str(mixed)], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 1 and "is a directory" in res.stderr


def test_clamped_halves_are_reported_in_the_commands_words(tmp_path, capsys):
    # A value beyond half's range: convert and warp write half EXR by default, clamp it to half's largest
    # finite value, (2 - 2**-10) * 2**15 = 65504 (IEEE 754 binary16), and name the option that keeps it.
    pano = np.full((8, 16, 3), 1e6, np.float32)
    lio.write(tmp_path / "sun.pfm", pano)
    for argv in (["convert", str(tmp_path / "sun.pfm"), "--to", "exr", "-o", str(tmp_path / "c.exr")],
                 ["warp", str(tmp_path / "sun.pfm"), "-o", str(tmp_path / "w.exr"), "--to", "equirect",
                  "--size", "16x8", "--quiet"]):
        assert main(argv) == 0
        err = capsys.readouterr().err
        assert "write with --pixel-type float to keep them" in err and "pixel_type" not in err
    assert lio.read(tmp_path / "c.exr")[0].max() == (2 - 2**-10) * 2**15
    assert main(["convert", str(tmp_path / "sun.pfm"), "--to", "exr", "-o", str(tmp_path / "f.exr"),
                 "--pixel-type", "float"]) == 0
    assert "--pixel-type" not in capsys.readouterr().err
    assert lio.read(tmp_path / "f.exr")[0].max() == 1e6
