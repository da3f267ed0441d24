"""sRGB in one place: lenslab.srgb against colour-science, the file formats' tables built from it, and
the commands' light paths that no longer import colour-science or numba."""

from __future__ import annotations

import json
import subprocess
import sys

import colour
import numpy as np
import pytest

from lenslab import srgb
from lenslab.io import encode

# dense codes and values, with both sides of each segment's knee
GRID = np.unique(np.concatenate([np.linspace(0.0, 1.0, 200001), np.geomspace(1e-9, 1.0, 20001),
                                 np.nextafter(0.04045, [0.0, 1.0]), np.nextafter(0.0031308, [0.0, 1.0]),
                                 [0.040449936, 0.04045, 0.0031308]]))


def test_encoding_agrees_with_colour_science_to_float32_precision():
    got = srgb.encode(GRID).astype(np.float64)
    ref = colour.models.eotf_inverse_sRGB(GRID)
    # linear interpolation in 65537 points: the curve's bend is strongest just above the knee, where
    # h^2 / 8 |f''| = 7e-8; float32 rounding of values near 1 adds 6e-8
    np.testing.assert_allclose(got, ref, rtol=0, atol=1.3e-7)
    x = np.array([np.nan, -1.0, 0.5, 2.0, np.inf, -np.inf])
    # bad values as 0 or 1, then the same bound as above
    np.testing.assert_allclose(srgb.encode(x), colour.models.eotf_inverse_sRGB([0, 0, 0.5, 1, 1, 0]), atol=1.3e-7)
    assert srgb.encode(np.zeros((2, 3))).shape == (2, 3) and srgb.encode([1.0])[0] == 1.0


@pytest.mark.parametrize("maxval", [1, 255, 1023, 65535])
def test_decode_tables_equal_colour_science(maxval):
    codes = np.arange(maxval + 1) / maxval
    np.testing.assert_array_equal(srgb.decode_table(maxval), np.float32(colour.models.eotf_sRGB(codes)))
    assert srgb.KNEE == pytest.approx(0.04045, abs=1e-7)  # the standard's rounded knee


@pytest.mark.parametrize("bits", [8, 16])
def test_table_encoding_rounds_colour_sciences_encoding(bits):
    maxval = (1 << bits) - 1
    rng = np.random.default_rng(bits)
    x = np.concatenate([rng.random(200000), rng.random(20000) ** 6]).astype(np.float32)
    ref = np.floor(maxval * colour.models.eotf_inverse_sRGB(x.astype(np.float64)) + 0.5)
    np.testing.assert_array_equal(encode.encode_quantise(x, bits, dither=False), ref)


def test_tables_are_built_once_and_kept(tmp_path, monkeypatch):
    monkeypatch.setenv("LENSLAB_CACHE_DIR", str(tmp_path))
    srgb.decode_table.cache_clear()
    try:
        table = srgb.decode_table(255)
        (path,) = tmp_path.glob("srgb-*-decode-255.npy")
        np.testing.assert_array_equal(np.load(path), table)
        path.write_bytes(b"not a table")  # a damaged file is rebuilt, never trusted
        srgb.decode_table.cache_clear()
        np.testing.assert_array_equal(srgb.decode_table(255), np.float32(colour.models.eotf_sRGB(np.arange(256) / 255)))
    finally:
        srgb.decode_table.cache_clear()


def _loaded_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys, json\n"
                          "print(json.dumps(sorted({m.split('.')[0] for m in sys.modules})))"],
                         check=True, capture_output=True, text=True).stdout
    return set(json.loads(out.strip().splitlines()[-1]))


def test_reading_tone_mapping_and_writing_ldr_import_neither_colour_science_nor_numba(tmp_path, monkeypatch):
    # the first run builds the sRGB tables into the cache (with colour-science); later runs only read them
    monkeypatch.setenv("LENSLAB_CACHE_DIR", str(tmp_path / "cache"))
    code = ("import numpy as np\n"
            "from lenslab import io, tone\n"
        f"p = {str(tmp_path / 'a.png')!r}\n"
            "img = np.random.default_rng(0).random((16, 32, 3)).astype(np.float32) * 4\n"
            "for mode in ('per-channel', 'luminance'):\n"
            "    for curve in ('hable', 'agx', 'reinhard2002'):\n"
            "        io.write(p, tone.tonemap(img, curve, 'auto', mode), overwrite=True)\n"
            "io.read(p)\n")
    assert "colour" in _loaded_after(code)
    loaded = _loaded_after(code)
    assert not loaded & {"colour", "numba", "scipy"}, sorted(loaded & {"colour", "numba", "scipy"})


@pytest.mark.parametrize("space", ["sRGB", "ITU-R BT.2020", "Display P3", "ACEScg"])
def test_luminance_weights_from_chromaticities_equal_colour_science(space):
    from lenslab import tone

    cs = colour.RGB_COLOURSPACES[space]
    xy = np.vstack([cs.primaries, cs.whitepoint])
    ref = colour.normalised_primary_matrix(cs.primaries, cs.whitepoint)[1]
    # computed in float64 by SMPTE RP 177 as colour-science does, returned as float32: one rounding
    np.testing.assert_allclose(tone.luminance_weights(xy), ref, rtol=1e-7, atol=0)
    # a name goes to colour-science's own matrix (sRGB: the standard's published row, no import)
    np.testing.assert_allclose(tone.luminance_weights(space), cs.matrix_RGB_to_XYZ[1], rtol=1e-7, atol=0)
