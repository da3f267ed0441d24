"""An image that records a mirrored camera (a ``lenslab warp --flip`` output) named as a camera outside ``warp``:
``lenslab camera convert`` refuses it in one line (a calibration file holds a lens and no mirror, so the file would
read the flop's pixels back mirrored) and ``camera show`` names its mirror; ``lenslab validate --reference-camera``
(and ``--to`` for a reference without a camera) takes its lens with its mirror; a scene's ``validate --to`` refuses
it in one line (its render would be of the unmirrored view).

Outside values: a flop (``--flip h``, no turn) is the unflipped warp of the same lens read right to left (NumPy's
``[:, ::-1]``), so a reference camera that keeps the mirror sees the flop exactly (bilinear at pixel centres of the
same rays: float32 rounding), and one that drops it sees the unflipped warp, off by the panorama's whole gradient."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write

W, H = 40, 30
SPEC = "perspective:fov=70"


def _views(tmp_path):
    """A smooth equirect (no two columns alike), its flop (``--flip h``) and its unflipped warp into SPEC."""
    y, x = np.mgrid[0:128, 0:256].astype(np.float64)
    img = np.stack([1.5 + np.sin(x / 9.0), 1.5 + np.cos(y / 7.0), 0.2 + (x + 3 * y) / 640.0], axis=-1)
    pano = tmp_path / "pano.exr"
    write(pano, img.astype(np.float32), pixel_type="float")
    views = {}
    for name, flip in (("flop", ["--flip", "h"]), ("plain", [])):
        views[name] = tmp_path / f"{name}.exr"
        assert main(["warp", str(pano), "-o", str(views[name]), "--to", SPEC, "--size", f"{W}x{H}",
                     "--pixel-type", "float", "-q", *flip]) == 0
    # the flop is the unflipped view read right to left (float32 rounding of the same bilinear taps)
    np.testing.assert_allclose(read(views["flop"])[0], read(views["plain"])[0][:, ::-1], rtol=1e-5, atol=1e-6)
    return pano, views


def test_camera_convert_refuses_a_flop_in_one_line(tmp_path, capsys):
    _, views = _views(tmp_path)
    out = tmp_path / "cam.toml"
    assert main(["camera", "convert", str(views["flop"]), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "mirror h" in err and str(views["flop"]) in err
    assert not out.exists()
    # the unmirrored view converts: its lens is all its camera
    assert main(["camera", "convert", str(views["plain"]), "-o", str(out)]) == 0
    assert "[lens]" in out.read_text() and "mirror" not in out.read_text()
    # show names the mirror its lens cannot carry
    assert main(["camera", "show", str(views["flop"])]) == 0
    assert "  mirror   h " in capsys.readouterr().out


@pytest.mark.parametrize("name", ["flop", "plain"])
def test_validate_reference_camera_keeps_the_mirror_of_an_image(tmp_path, name):
    pano, views = _views(tmp_path)
    ref = views[name]
    report = tmp_path / "report"
    main(["validate", "--reference", str(ref), "--reference-camera", str(ref), "--source", str(pano),
          "--from", "equirect", "--filters", "bilinear", "-o", str(report), "-q"])
    data = json.loads((report / "reference.json").read_text())
    assert data["reference_pose"].get("mirror", "") == ("h" if name == "flop" else "")
    (row,) = data["settings"]
    # the same rays, the same bilinear taps, float32 pixels: a few ulps of values near 2
    assert row["max_error"] < 1e-5


def test_validate_to_an_image_keeps_its_mirror_for_a_reference_without_camera(tmp_path):
    pano, views = _views(tmp_path)
    bare = tmp_path / "bare.exr"  # the flop's pixels in a file that records no camera
    write(bare, read(views["flop"])[0], pixel_type="float")
    report = tmp_path / "report"
    main(["validate", "--reference", str(bare), "--to", str(views["flop"]), "--source", str(pano),
          "--from", "equirect", "--filters", "bilinear", "-o", str(report), "-q"])
    data = json.loads((report / "reference.json").read_text())
    assert data["reference_pose"]["mirror"] == "h"
    (row,) = data["settings"]
    assert row["max_error"] < 1e-5  # as above: the same rays and taps, float32 pixels


def test_validate_of_a_scene_refuses_to_a_flop_in_one_line(tmp_path, capsys):
    # a scene's render and its warps take --to's lens posed by the scene: a flop's view would not be the one validated
    _, views = _views(tmp_path)
    report = tmp_path / "report"
    assert main(["validate", "--to", str(views["flop"]), "--size", "32x32", "-o", str(report), "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "mirror h" in err and f"--to {SPEC}" in err
    assert not report.exists()
