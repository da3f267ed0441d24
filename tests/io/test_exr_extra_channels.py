"""`lenslab convert` from EXR keeps the channels that are not colour (depth ``Z``, normals ``N.x``...) when the
output is EXR, each in its stored type and its data window, and says in one note line which it drops for formats that
cannot hold them. The values expected are OpenImageIO's reading of the source file."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

oiio = pytest.importorskip("OpenImageIO")
OpenEXR = pytest.importorskip("OpenEXR")

EXTRA = ["N.x", "N.y", "N.z", "Z"]


@pytest.fixture
def layered(tmp_path):
    """R, G, B (half), Z (float) and N.x, N.y, N.z (half) in a data window inside the display window."""
    rng = np.random.default_rng(5)
    h, w = 20, 30
    chans = {c: rng.uniform(0, 2, (h, w)).astype(np.float16) for c in "RGB"}
    chans["Z"] = rng.uniform(1, 1e4, (h, w)).astype(np.float32)
    for c in ("N.x", "N.y", "N.z"):
        chans[c] = rng.uniform(-1, 1, (h, w)).astype(np.float16)
    header = {"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION,
              "dataWindow": (np.array([5, 3], np.int32), np.array([5 + w - 1, 3 + h - 1], np.int32)),
              "displayWindow": (np.array([0, 0], np.int32), np.array([39, 29], np.int32))}
    path = tmp_path / "layered.exr"
    OpenEXR.File(header, chans).write(str(path))
    return path


def _oiio_channels(path) -> dict:
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    pix = inp.read_image(format="float")
    inp.close()
    window = (spec.x, spec.y, spec.width, spec.height)
    return {n: pix[..., i] for i, n in enumerate(spec.channelnames)}, window, spec


def _convert(src, dst, to):
    return subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", to, "-o", str(dst)],
                          capture_output=True, text=True)


def test_exr_to_exr_keeps_depth_and_normals(layered, tmp_path):
    src, (x, y, w, h), _ = _oiio_channels(layered)
    out = tmp_path / "out.exr"
    run = _convert(layered, out, "exr")
    assert run.returncode == 0, run.stderr
    assert "not written" not in run.stderr
    got, (ox, oy, ow, oh), spec = _oiio_channels(out)
    assert set(EXTRA) <= set(got)
    types = {n: str(spec.channelformat(i)) for i, n in enumerate(spec.channelnames)}
    assert types["Z"] == "float" and types["N.x"] == "half"  # each in its stored type
    # the data window kept where the source stores it (as oiiotool keeps it): no 0 depth outside it
    assert (ox, oy, ow, oh) == (x, y, w, h) == (5, 3, 30, 20)
    assert (spec.full_x, spec.full_y, spec.full_width, spec.full_height) == (0, 0, 40, 30)
    for name in EXTRA + list("RGB"):
        np.testing.assert_array_equal(got[name], src[name])


@pytest.mark.parametrize("to", ["png", "tiff", "pfm"])
def test_other_formats_say_in_one_line_which_channels_they_drop(layered, tmp_path, to):
    run = _convert(layered, tmp_path / f"out.{to}", to)
    assert run.returncode == 0, run.stderr
    notes = [ln for ln in run.stderr.splitlines() if "not written" in ln]
    assert len(notes) == 1
    for name in EXTRA:
        assert f"'{name}'" in notes[0]
    assert str(layered) in notes[0]


def test_a_plain_rgb_exr_gives_no_note(tmp_path):
    path = tmp_path / "rgb.exr"
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION},
                 {"RGB": np.ones((4, 5, 3), np.float16)}).write(str(path))
    run = _convert(path, tmp_path / "out.png", "png")
    assert run.returncode == 0 and "not written" not in run.stderr
