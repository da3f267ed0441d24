"""HDR displays through OpenColorIO: a colorimetric view puts scene 1.0 on BT.2408's reference white
(203 cd/m², ITU-R BT.2408), so a PQ PNG reads back at the light it was made of; formats with no tag that
says PQ or HLG are refused in one line. Expected values: colour-science's ST 2084 EOTF of the file's codes
and PyOpenColorIO's own processor."""

from __future__ import annotations

import subprocess
import sys

import cv2
import numpy as np
import pytest

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")
colour = pytest.importorskip("colour")

import lenslab.io as lio  # noqa: E402

GREYS = np.array([0.05, 0.18, 1.0, 2.0, 4.0, 10.0])
PQ_DISPLAY = "Rec.2100-PQ - Display"


def _scene(tmp_path):
    img = np.repeat(np.repeat(GREYS[None, :, None], 3, axis=2), 2, axis=0).astype(np.float32)  # 2 x 6 greys
    lio.write(tmp_path / "s.exr", img, pixel_type="float")
    return tmp_path / "s.exr"


def _lenslab(*args):
    return subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)


def test_opencolorio_itself_puts_one_at_100_nits():
    # the side that differs from BT.2408: the config's PQ display is scaled 1.0 = 100 cd/m2
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://default")
    cpu = cfg.getProcessor("Linear Rec.709 (sRGB)", PQ_DISPLAY, "Un-tone-mapped",
                           PyOpenColorIO.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    px = np.ones((1, 1, 3), np.float32)
    cpu.applyRGB(px)
    assert colour.models.eotf_ST2084(float(px[0, 0, 1])) == pytest.approx(100.0, rel=1e-4)


@pytest.mark.parametrize("view", ["Un-tone-mapped", "Video (colorimetric)"])
def test_a_pq_png_puts_scene_white_at_203_nits_and_reads_back(tmp_path, view):
    src = _scene(tmp_path)
    out = tmp_path / "pq.png"
    run = _lenslab("convert", src, "--to", "png", "--display", "rec.2100-pq", "--view", view, "-o", out)
    assert run.returncode == 0, run.stderr
    codes = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[0, :, 1].astype(np.float64) / 65535
    nits = colour.models.eotf_ST2084(codes)
    # 16-bit PQ codes: one code step is < 0.03 % of the light from 1 to 2100 cd/m2 (ST 2084's slope)
    np.testing.assert_allclose(nits, 203.0 * GREYS, rtol=3e-4)
    back, _ = lio.read(out)  # lenslab reads PQ with 1.0 = 203 cd/m2: the greys it was made of, not 0.49 of them
    np.testing.assert_allclose(back[0, :, 1], GREYS, rtol=3e-4)


def test_a_tone_mapping_view_is_left_as_opencolorio_makes_it(tmp_path):
    src = _scene(tmp_path)
    out = tmp_path / "aces.png"
    view = "ACES 2.0 - HDR 1000 nits (Rec.2020)"
    assert _lenslab("convert", src, "--to", "png", "--display", "rec.2100-pq", "--view", view, "-o", out).returncode == 0
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://default")
    cpu = cfg.getProcessor("Linear Rec.709 (sRGB)", PQ_DISPLAY, view,
                           PyOpenColorIO.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    want = np.repeat(GREYS[None, :, None], 3, axis=2).astype(np.float32)
    cpu.applyRGB(want)
    got = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[0, :, 1].astype(np.float64)
    assert np.abs(got - np.clip(want[0, :, 1], 0, 1) * 65535).max() <= 0.5 + 65535 * 1e-5  # rounding + OCIO's float32


@pytest.mark.parametrize("to", ["tiff", "ppm", "exr"])
def test_formats_without_a_transfer_tag_are_refused_in_one_line(tmp_path, to):
    src = _scene(tmp_path)
    out = tmp_path / f"pq.{to}"
    run = _lenslab("convert", src, "--to", to, "--display", "rec.2100-pq", "-o", out)
    assert run.returncode == 2 and not out.exists()
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and "PQ" in lines[0] and "PNG" in lines[0] and "cICP" in lines[0]
