"""A file whose profile has sRGB's own primaries but another curve (a gamma 2.2 or a linear "sRGB" profile, as
scRGB and esRGB are) holds no colour outside the sRGB gamut: written as an sRGB PNG it is never said to have
any, however its profile's s15.16 colorants round.

Outside value: colour-science's sRGB and BT.709 primaries, the same: no colour of the file lies outside. The
profile's colorants, as littleCMS reads them, are adapted back from D50 by colour-science's Bradford and
checked against them first (within 1e-4: s15.16 numbers and the adaptation). Converted by such a matrix, a
saturated colour takes a component of about -1e-4 (colour-science's own sRGB -> BT.709 matrix has entries of
-8e-5, from the white points' rounding): within the file's precision, not a colour outside.
"""

from __future__ import annotations

import io
import struct

import numpy as np
import pytest

from lenslab.cli.main import main

colour = pytest.importorskip("colour")
from PIL import Image  # noqa: E402

from lenslab.io.colour import icc_build  # noqa: E402
from lenslab.io.colour.icc_chunks import png_with_profile  # noqa: E402
from tests.io.test_icc_profiles import _retagged  # noqa: E402

#: ICC.1 parametric curves: (function, parameters) of a gamma 2.2 and of the identity
CURVES = {"gamma 2.2": (0, [2.2]), "linear": (0, [1.0])}


def _srgb_primaries_profile(curve: str, monkeypatch) -> bytes:
    """lenslab's own profile writer on colour-science's sRGB primaries and white, with ``curve``."""
    monkeypatch.setitem(icc_build.SPACES, "sRGB", "sRGB")
    data = icc_build.profile.__wrapped__("sRGB")  # (not cached: the writer's table of displays stays as it is)
    function, params = CURVES[curve]
    body = b"para" + bytes(4) + struct.pack(">H", function) + bytes(2)
    body += b"".join(struct.pack(">i", round(v * 65536)) for v in params)
    return _retagged(data, (b"rTRC", b"gTRC", b"bTRC"), body)


@pytest.mark.parametrize("curve", sorted(CURVES))
def test_a_profile_on_srgb_primaries_has_no_colour_outside_srgb(tmp_path, capsys, monkeypatch, curve):
    from PIL import ImageCms

    icc = _srgb_primaries_profile(curve, monkeypatch)
    prof = ImageCms.ImageCmsProfile(io.BytesIO(icc)).profile
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    d50 = np.array([0.9642, 1.0, 0.8249])  # the connection space's white (ICC.1 7.2.16)
    back = [colour.adaptation.chromatic_adaptation_VonKries(np.array(c[0]), d50, colour.xy_to_XYZ(srgb.whitepoint),
                                                         "Bradford")
            for c in (prof.red_colorant, prof.green_colorant, prof.blue_colorant)]  # as littleCMS reads them
    assert np.allclose(colour.XYZ_to_xy(np.array(back)), srgb.primaries, atol=1e-4)  # s15.16 and Bradford
    assert np.array_equal(srgb.primaries, colour.RGB_COLOURSPACES["ITU-R BT.709"].primaries)
    codes = np.random.default_rng(5).integers(0, 256, (24, 32, 3), dtype=np.uint8)
    codes[0, :6] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0], [0, 255, 255], [255, 0, 255]]
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")
    src = tmp_path / "srgb-primaries.png"
    src.write_bytes(png_with_profile(buf.getvalue(), icc))
    assert main(["convert", str(src), "--to", "png", "-o", str(tmp_path / "out.png")]) == 0
    assert main(["tonemap", str(src), "-o", str(tmp_path / "tone.png")]) == 0
    err = capsys.readouterr().err
    assert "outside the sRGB gamut" not in err, err
