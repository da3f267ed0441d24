"""The count of colours outside the sRGB gamut leaves out the conversion's rounding: a saturated Adobe RGB ramp
(every colour with one code 0: the faces of the RGB cube where the gamut's edge lies) read through Ghostscript's
Adobe RGB profile counts the pixels colour-science counts in float64 with the same edge
(``lenslab.io.colour.gamut.EDGE`` times the pixel's largest component magnitude).

Outside values: colour-science's Adobe RGB (1998) decoding and its matrix to BT.709, in float64. Its matrix and
the profile's differ (the standard's four-decimal matrix against s15.16 colorants adapted from D50): on this
ramp the two linear colours differ by at most 3.04e-5 of the pixel's magnitude, so pixels whose colour-science
margin to the edge is within 4e-5 of their magnitude may fall either way; lenslab's count lies between
colour-science's count without them and with them. Adobe RGB's red is sRGB's red (chromaticity 0.64, 0.33):
its ramp is inside the gamut, though both matrices give it a G of about -1e-5 of R.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read
from lenslab.io.colour.gamut import EDGE, outside
from lenslab.io.colour.icc_chunks import png_with_profile

colour = pytest.importorskip("colour")
from PIL import Image  # noqa: E402

PROFILE = Path("/usr/share/color/icc/ghostscript/a98.icc")  # Debian's libgs-common, which .ci/run installs
APART = 4e-5  # the two conversions' largest difference on the ramp (3.04e-5 of the magnitude), and a margin


def _ramp() -> np.ndarray:
    i, j = np.meshgrid(np.arange(256), np.arange(256), indexing="ij")
    z = np.zeros_like(i)
    return np.concatenate([np.stack(face, -1) for face in [(i, j, z), (z, i, j), (j, z, i)]], axis=1).astype(np.uint8)


def _png(path: Path, codes: np.ndarray) -> Path:
    if not PROFILE.is_file():
        pytest.skip(f"{PROFILE} is absent (Debian's libgs-common, which .ci/run installs)")
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")
    path.write_bytes(png_with_profile(buf.getvalue(), PROFILE.read_bytes()))
    return path


def _margins(codes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """colour-science's lowest component of each pixel past the edge (negative: outside), and the magnitude."""
    y = colour.RGB_to_RGB(codes / 255, "Adobe RGB (1998)", "ITU-R BT.709", None, apply_cctf_decoding=True)
    low = y.min(axis=-1)
    magnitude = np.maximum(y.max(axis=-1), -low)
    return low + EDGE * magnitude, magnitude


def test_a_saturated_adobe_ramp_counts_as_colour_science_counts(tmp_path, capsys):
    codes = _ramp()
    margin, magnitude = _margins(codes)
    sure = int(np.count_nonzero(margin < -APART * magnitude))
    either = int(np.count_nonzero(np.abs(margin) <= APART * magnitude))
    assert sure > 100_000 and either < 0.01 * sure  # most of the faces are outside, few pixels undecided
    path = _png(tmp_path / "ramp.png", codes)
    image, _ = read(path)
    count = outside(image)
    assert sure <= count <= sure + either
    assert main(["convert", str(path), "--to", "png", "-o", str(tmp_path / "out.png")]) == 0
    assert f"{count} of {codes.shape[0] * codes.shape[1]} pixels hold colours outside" in capsys.readouterr().err


def test_adobe_red_is_inside(tmp_path, capsys):
    codes = np.zeros((1, 256, 3), np.uint8)
    codes[0, :, 0] = np.arange(256)
    margin, _ = _margins(codes)
    assert (margin >= 0).all()  # colour-science: within the edge (its G is -1.03e-5 of R)
    path = _png(tmp_path / "red.png", codes)
    image, _ = read(path)
    assert image[0, 51, 1] < 0 and outside(image) == 0  # the profile's G of red 51 is -5.8e-8: rounding
    assert main(["convert", str(path), "--to", "png", "-o", str(tmp_path / "out.png")]) == 0
    err = capsys.readouterr().err
    assert "gamut" not in err and "negative" not in err
    assert np.asarray(Image.open(tmp_path / "out.png"))[0, :, 1:].max() == 0
