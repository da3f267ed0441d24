"""``lenslab warp --compat v360`` writes a PNG with the channels ffmpeg's v360 writes on the same
command: v360 keeps its input's pixel format, so an RGB source gives an RGB image and an RGBA source an RGBA
one. The channel counts of both files are OpenImageIO's; ffmpeg's are read from its own output each run (Debian's
ffmpeg, which CI installs), not written into the test. The colour of every pixel is the same whether or not
the alpha lenslab would have written (all 1: every pixel is covered) is there.
"""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")

#: the same view in both tools: an equirect panorama to a 90 x 60 degree perspective, 48 x 32 pixels
FFMPEG_VIEW = "v360=input=e:output=flat:h_fov=90:v_fov=60:w=48:h=32"
LENSLAB_VIEW = ["--from", "equirect", "--to", "perspective:fov=90,vfov=60", "--size", "48x32"]


def _ffmpeg() -> str:
    path = shutil.which("ffmpeg")
    assert path, "ffmpeg is needed (CI installs Debian's); apt-get install ffmpeg"
    return path


def _write(path, pixels: np.ndarray) -> None:
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], "uint8"))
    assert out.write_image(pixels)
    out.close()


def _read(path) -> np.ndarray:
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    pixels = inp.read_image("uint8")
    inp.close()
    return pixels


def _source(channels: int) -> np.ndarray:
    y, x = np.mgrid[0:64, 0:128]
    rgb = np.stack([x * 2, y * 4, 255 - x], axis=-1).astype(np.uint8)
    return rgb if channels == 3 else np.dstack([rgb, np.full((64, 128), 255, np.uint8)])


@pytest.mark.parametrize("channels", [3, 4], ids=["RGB source", "RGBA source"])
def test_compat_v360_writes_the_channels_ffmpeg_writes(tmp_path, channels):
    ext = "png"
    src = tmp_path / f"pano.{ext}"
    _write(src, _source(channels))
    theirs, ours = tmp_path / f"ffmpeg.{ext}", tmp_path / f"lenslab.{ext}"
    subprocess.run([_ffmpeg(), "-v", "error", "-y", "-i", str(src), "-vf", FFMPEG_VIEW, str(theirs)], check=True)
    assert main(["warp", str(src), *LENSLAB_VIEW, "--compat", "v360", "-o", str(ours), "-q"]) == 0
    ffmpeg_channels = _read(theirs).shape[2]
    assert ffmpeg_channels == channels  # what v360 does, read from its file: it keeps the source's format
    assert _read(ours).shape[2] == ffmpeg_channels


def test_without_alpha_the_colour_is_the_covered_colour(tmp_path):
    """The RGB output's colour is the RGBA output's (every pixel covered: alpha 255, colour unchanged)."""
    for channels in (3, 4):
        _write(tmp_path / f"pano{channels}.png", _source(channels))
        assert main(["warp", str(tmp_path / f"pano{channels}.png"), *LENSLAB_VIEW, "--compat", "v360",
                     "-o", str(tmp_path / f"out{channels}.png"), "-q"]) == 0
    rgb, rgba = _read(tmp_path / "out3.png"), _read(tmp_path / "out4.png")
    assert (rgba[..., 3] == 255).all()
    np.testing.assert_array_equal(rgb, rgba[..., :3])


#: an equisolid output past its back pole: v360 writes zeros there (no ray), lenslab's coverage is 0
FFMPEG_BEYOND = "v360=input=e:output=equisolid:h_fov=300:v_fov=300:w=32:h=32"
LENSLAB_BEYOND = ["--from", "equirect", "--to", "fisheye:fov=300,mapping=equisolid", "--size", "32x32"]


def test_uncovered_pixels_do_not_add_alpha_to_an_rgb_output(tmp_path):
    """ffmpeg keeps the RGB format where it writes zeros, and so does --compat v360: those pixels are black,
    as ffmpeg's are (read from its file: the same pixels are zero in both)."""
    src, theirs, ours = tmp_path / "pano.png", tmp_path / "ffmpeg.png", tmp_path / "lenslab.png"
    _write(src, _source(3))
    subprocess.run([_ffmpeg(), "-v", "error", "-y", "-i", str(src), "-vf", FFMPEG_BEYOND, str(theirs)], check=True)
    assert main(["warp", str(src), *LENSLAB_BEYOND, "--compat", "v360", "-o", str(ours), "-q"]) == 0
    ff, ll = _read(theirs), _read(ours)
    zeros = (ff == 0).all(axis=-1)
    assert zeros.sum() > 100  # (the view has pixels past the back pole)
    assert ll.shape[2] == ff.shape[2] == 3
    assert (ll[zeros] == 0).all()

