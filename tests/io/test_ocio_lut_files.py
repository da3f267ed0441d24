"""An OpenColorIO config is a side file, and so is every LUT file its transforms name: a FileTransform
pointing at ``/dev/zero`` (OpenColorIO reads it without end), a FIFO (it waits for ever) or a huge
file is refused in one line before OpenColorIO opens it. The configs are written by PyOpenColorIO;
each command runs in a subprocess under an address-space limit."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

import lenslab.io as lio
from tests.hostile_run import run

ocio = pytest.importorskip("PyOpenColorIO")


def _config(folder, src: str, name: str = "lut.ocio"):
    """A config whose display 'bad' shows colour space 'lut': linear through a FileTransform of ``src``
    (inside a GroupTransform, as studio configs nest them)."""
    cfg = ocio.Config.CreateRaw()
    cfg.setSearchPath(str(folder))
    cfg.addColorSpace(ocio.ColorSpace(name="lin"))
    cs = ocio.ColorSpace(name="lut")
    cs.setTransform(ocio.GroupTransform([ocio.FileTransform(src=src, interpolation=ocio.INTERP_LINEAR)]),
                    ocio.COLORSPACE_DIR_FROM_REFERENCE)
    cfg.addColorSpace(cs)
    cfg.addDisplayView("bad", "lut", "lut")
    cfg.setActiveDisplays("bad")
    path = folder / name
    path.write_text(cfg.serialize())
    return path, cfg


def _convert(tmp_path, config):
    src = tmp_path / "p.exr"
    lio.write(src, np.full((8, 8, 3), 0.25, np.float32))
    out = tmp_path / "out"
    out.mkdir()
    done = run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", "png", "-o", str(out / "o.png"),
                "--ocio", str(config), "--display", "bad", "--colorspace", "lin"])
    return done, out


def _lut_fifo(tmp_path):
    path = tmp_path / "fifo.cube"
    os.mkfifo(path)
    return str(path), "FIFO"


def _lut_huge(tmp_path):
    path = tmp_path / "huge.cube"
    with open(path, "wb") as f:
        f.truncate(3 << 30)  # sparse: 3 GiB declared, no disk used
    return str(path), "more than"


@pytest.mark.parametrize("make", [lambda p: ("/dev/zero", "system path"), _lut_fifo, _lut_huge],
                         ids=["dev_zero", "fifo", "huge"])
def test_a_lut_file_that_is_not_a_bounded_regular_file_is_refused(tmp_path, make):
    lut, cause = make(tmp_path)
    config, _ = _config(tmp_path, lut)
    done, out = _convert(tmp_path, config)
    assert done.returncode == 1, done.stderr[-500:]
    assert "Traceback" not in done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, lines
    assert lut in lines[0] and str(config) in lines[0] and cause in lines[0], lines[0]
    assert list(out.iterdir()) == []


def test_a_regular_lut_file_on_the_search_path_is_used(tmp_path):
    """A small 1D LUT (Sony .spi1d, x -> x / 2 on [0, 1]) is read: the PNG holds OpenColorIO's own
    answer for 0.25 through it (0.125), as 8-bit code values."""
    (tmp_path / "half.spi1d").write_text("Version 1\nFrom 0.0 1.0\nLength 2\nComponents 1\n{\n    0.0\n    0.5\n}\n")
    config, cfg = _config(tmp_path, "half.spi1d")
    done, out = _convert(tmp_path, config)
    assert done.returncode == 0, done.stderr
    cpu = cfg.getProcessor("lin", "bad", "lut", ocio.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    expected = np.array(cpu.applyRGB([0.25, 0.25, 0.25]), np.float64)
    assert np.allclose(expected, 0.125)
    import cv2

    codes = cv2.imread(str(out / "o.png"), cv2.IMREAD_UNCHANGED)  # the stored code values, as OpenCV reads them
    assert codes.dtype == np.uint8
    assert np.all(codes == np.round(expected * 255)), codes[0, 0]
