"""``lenslab tonemap --help`` says what a TIFF output holds, as it does for the other formats: display-linear floats,
or with ``--bits 8|16`` sRGB-encoded integers of that depth. It named TIFF among neither the LDR nor the float outputs,
and gave ``--bits`` to PNG/PPM/PGM only, though a TIFF takes it.

Outside values: the sample types tifffile reads from the files written (float32; uint8 and uint16), and the sRGB
encoding of IEC 61966-2-1 transcribed here (0.5 -> 12.92 * ... / 1.055 * 0.5 ** (1 / 2.4) - 0.055)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

tifffile = pytest.importorskip("tifffile")


def _srgb(v):
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def test_help_names_the_tiff_outputs(capsys):
    with pytest.raises(SystemExit):
        main(["tonemap", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "float outputs (EXR, PFM, and TIFF without --bits)" in text
    assert "bit depth for PNG/PPM/PGM output (default 8), and for TIFF: sRGB-encoded integers instead of floats" in text


@pytest.mark.parametrize("bits, dtype", [(None, np.float32), (8, np.uint8), (16, np.uint16)])
def test_tiff_holds_what_help_says(tmp_path, bits, dtype):
    src = tmp_path / "grey.exr"
    write(src, np.full((4, 4, 3), 0.5, np.float32), pixel_type="float")
    out = tmp_path / "out.tiff"
    extra = [] if bits is None else ["--bits", str(bits)]
    assert main(["tonemap", str(src), "-o", str(out), "--tone", "clamp", "--no-dither", "-q", *extra]) == 0
    got = tifffile.imread(out)
    assert got.dtype == dtype
    if bits is None:
        assert np.allclose(got, 0.5, atol=1e-6)  # display-linear: the clamp curve leaves 0.5 as it is
    else:
        assert np.all(got == np.round(_srgb(0.5) * (2 ** bits - 1)))
