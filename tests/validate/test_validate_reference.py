"""``lenslab validate --reference FILE``: warps measured against the user's own reference image.

The scene is a radiance that is a closed-form function of direction, ``L(d) = 1 + 0.5 d_x + 0.25 d_y +
0.2 d_z^2``; the panorama and the reference (an equidistant 180-degree fisheye) are evaluated from it at
their pixel centres with the projection formulas written here in float64 (docs/conventions.md), not
by lenslab. The report's figures are checked against OpenImageIO's ``compare`` of the same pixels."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write
from lenslab.lenses import Camera

oiio = pytest.importorskip("OpenImageIO")


def radiance(d):
    v = 1.0 + 0.5 * d[..., 0] + 0.25 * d[..., 1] + 0.2 * d[..., 2] ** 2
    return np.stack([v, 0.5 * v, 2.0 - v], axis=-1)


def panorama(w, h):
    y, x = np.mgrid[0:h, 0:w] + 0.5
    phi, theta = (2 * x / w - 1) * math.pi, (1 - 2 * y / h) * math.pi / 2
    d = np.stack([np.cos(theta) * np.sin(phi), np.sin(theta), np.cos(theta) * np.cos(phi)], axis=-1)
    return radiance(d).astype(np.float32)


def fisheye_reference(n, fov=180.0):
    """Equidistant fisheye, the circle inscribed in the square: a = r F; alpha 1 inside, 0 outside."""
    y, x = np.mgrid[0:n, 0:n] + 0.5
    u, v = 2 * x / n - 1, 1 - 2 * y / n
    r = np.hypot(u, v)
    a = r * math.radians(fov) / 2
    k = np.where(r > 0, np.sin(a) / np.where(r > 0, r, 1), 0)
    d = np.stack([k * u, k * v, np.cos(a)], axis=-1)
    inside = r <= 1
    img = np.where(inside[..., None], radiance(d), 0.0)
    return np.concatenate([img, inside[..., None]], axis=-1).astype(np.float32)


@pytest.fixture
def files(tmp_path):
    write(tmp_path / "pano.exr", panorama(512, 256), pixel_type="float")
    ref = fisheye_reference(96)
    write(tmp_path / "ref.exr", ref, pixel_type="float")
    # the same reference with its camera recorded in the file
    write(tmp_path / "ref_cam.exr", ref, pixel_type="float", camera=Camera.from_spec("fisheye:fov=180", (96, 96)))
    return tmp_path


def test_report_ranks_settings_and_agrees_with_openimageio(files, capsys):
    out = files / "rep"
    code = main(["validate", "--reference", str(files / "ref.exr"), "--reference-camera", "fisheye:fov=180",
                 "--source", str(files / "pano.exr"), "--filters", "nearest,bilinear", "--no-flip",
                 "--fail", "0.05", "--warn", "0.01", "-o", str(out)])
    assert code == 0
    report = json.loads((out / "reference.json").read_text())
    rows = {r["label"]: r for r in report["settings"]}
    # bilinear interpolation of a smooth radiance at 0.7-degree pixels: its error is second order
    # ((0.0123 rad)^2 / 8 x |L''| <= 1 -> 2e-5); nearest is first order (half a pixel x |L'| <= 0.8 -> 5e-3)
    assert rows["bilinear"]["rms_error"] < 1e-4 < rows["nearest"]["rms_error"] < 1e-2
    assert report["best"] == "bilinear" and rows["bilinear"]["verdict"] == "PASS"
    assert rows["bilinear"]["pixels"] > 0.7 * 96 * 96 * math.pi / 4  # most of the circle is compared
    # the same figures from OpenImageIO on the compared pixels of the same warp
    from lenslab.warp import warp

    ref = fisheye_reference(96)
    img, alpha = warp(panorama(512, 256), Camera.from_spec("equirect", (512, 256)),
                      Camera.from_spec("fisheye:fov=180", (96, 96)), filter="bilinear")
    keep = (alpha >= 0.999) & (ref[..., 3] >= 0.999)
    cr = oiio.ImageBufAlgo.compare(oiio.ImageBuf(np.ascontiguousarray(ref[keep][None, :, :3])),
                                   oiio.ImageBuf(np.ascontiguousarray(img[keep][None])), 0.05, 0.01)
    assert rows["bilinear"]["rms_error"] == pytest.approx(cr.rms_error, rel=1e-7)
    assert rows["bilinear"]["mean_error"] == pytest.approx(cr.meanerror, rel=1e-7)
    assert rows["bilinear"]["max_error"] == pytest.approx(cr.maxerror, rel=1e-6)
    assert "PASS" in capsys.readouterr().out


def test_reference_camera_comes_from_the_file(files, capsys):
    out = files / "rep2"
    assert main(["validate", "--reference", str(files / "ref_cam.exr"), "--source", str(files / "pano.exr"),
                 "--filters", "bilinear", "--no-flip", "-o", str(out)]) == 0
    report = json.loads((out / "reference.json").read_text())
    assert report["reference_camera"].startswith("fisheye:fov=180")
    assert report["settings"][0]["rms_error"] < 1e-4
    # an earlier report is replaced only with --overwrite
    before = (out / "reference.json").read_bytes()
    assert main(["validate", "--reference", str(files / "ref_cam.exr"), "--source", str(files / "pano.exr"),
                 "--filters", "nearest", "--no-flip", "-o", str(out)]) == 1
    assert (out / "reference.json").read_bytes() == before


def test_reference_options_need_a_reference(files):
    assert main(["validate", "--reference-camera", "fisheye:fov=180", "-o", str(files / "r3")]) == 2
    assert not (files / "r3").exists()


def test_without_a_source_the_scene_panorama_is_rendered(tmp_path):
    """No --source: a panorama of --scene is rendered from the reference's eye and warped. The reference
    is the analytic sky at the fisheye's pixel centres (radiance written by the sky's closed form):
    with 1 sample per pixel at both ends, only the bilinear resampling error of a 1024x512 panorama is left."""
    from lenslab.validate.sources import AnalyticSource

    cam = Camera.from_spec("fisheye:fov=180", (64, 64))
    ref = AnalyticSource().render(cam, spp=1, seed=None)
    write(tmp_path / "ref.exr", np.concatenate([ref.image, ref.alpha[..., None]], axis=-1), pixel_type="float")
    assert main(["validate", "--reference", str(tmp_path / "ref.exr"), "--reference-camera", "fisheye:fov=180",
                 "--scene", "analytic", "--noise-free", "--pano-sizes", "1024x512", "--spp", "1",
                 "--filters", "bilinear", "--no-flip", "-o", str(tmp_path / "rep")]) == 0
    report = json.loads((tmp_path / "rep" / "reference.json").read_text())
    assert report["source"] == "analytic panorama 1024x512"
    row = report["settings"][0]
    assert row["pixels"] > 0.7 * 64 * 64 * math.pi / 4
    # the sky's sun and horizon are sharp: a few pixels on them differ by much, the rest by little
    # (measured 0.0076 mean relative error for bilinear, 0.0056 for nearest: sharp edges favour it)
    assert row["per_channel"][0]["mean_rel"] < 0.02
