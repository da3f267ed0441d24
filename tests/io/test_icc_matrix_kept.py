"""A file's primaries matrix is colour-science's, and kept: the second read of a Display P3 file (a phone's photo)
imports no colour-science (about 1 s of CPU) and reads the same floats.

Expected values from outside lenslab: colour-science's sRGB decoding and its Display P3 -> BT.709 matrix in
float64 (tolerance 2e-5 of linear light, as in ``test_icc_profiles.py``: the profile's colorants are s15.16
numbers, 7.6e-6 each, and its para curve's parameters too), and colour-science's ``matrix_RGB_to_RGB`` of the
primaries given (1e-12: the same float64 arithmetic, kept in a file and read back).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

colour = pytest.importorskip("colour")
tifffile = pytest.importorskip("tifffile")

from lenslab.io.colour.icc_build import profile as build_profile  # noqa: E402

READ = """
import sys, json, numpy as np
import lenslab.io as lio
image, meta = lio.read(sys.argv[1])
np.save(sys.argv[2], image)
print(json.dumps({"colour": "colour" in sys.modules}))
"""


def _read_in_a_process(path, out, cache) -> bool:
    env = {**os.environ, "LENSLAB_CACHE_DIR": str(cache)}
    done = subprocess.run([sys.executable, "-c", READ, str(path), str(out)], env=env, capture_output=True, text=True,
                          check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])["colour"]


def test_a_p3_file_read_again_imports_no_colour_science_and_reads_the_same(tmp_path):
    codes = np.random.default_rng(5).integers(0, 65536, (24, 32, 3), dtype=np.uint16)
    tifffile.imwrite(tmp_path / "p3.tif", codes, photometric="rgb", iccprofile=build_profile("Display P3"))
    cache = tmp_path / "cache"
    first = _read_in_a_process(tmp_path / "p3.tif", tmp_path / "a.npy", cache)
    again = _read_in_a_process(tmp_path / "p3.tif", tmp_path / "b.npy", cache)
    assert first and not again  # colour-science made the matrix once
    a, b = np.load(tmp_path / "a.npy"), np.load(tmp_path / "b.npy")
    assert a.tobytes() == b.tobytes()
    p3_to_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["Display P3"], colour.RGB_COLOURSPACES["ITU-R BT.709"])
    want = colour.cctf_decoding(codes / 65535.0, "sRGB") @ p3_to_709.T
    np.testing.assert_allclose(b, want, rtol=0, atol=2e-5)


@pytest.mark.parametrize("adaptation", [None, "Bradford"])
def test_the_kept_matrix_is_colour_sciences(tmp_path, monkeypatch, adaptation):
    from lenslab.io.colour.primaries import matrix_from_chromaticities

    monkeypatch.setenv("LENSLAB_CACHE_DIR", str(tmp_path))
    xy = [0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290]  # BT.2020's primaries and D65
    bt2020 = colour.RGB_COLOURSPACES["ITU-R BT.2020"]
    want = colour.matrix_RGB_to_RGB(bt2020, colour.RGB_COLOURSPACES["ITU-R BT.709"], adaptation)
    made = matrix_from_chromaticities(xy, adaptation)
    kept = matrix_from_chromaticities(xy, adaptation)
    assert len(list(tmp_path.iterdir())) == 1
    np.testing.assert_allclose(made, want, rtol=0, atol=1e-12)
    assert made.shape == kept.shape == (3, 3) and made.tobytes() == kept.tobytes()
    other = matrix_from_chromaticities([0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290], adaptation)
    np.testing.assert_allclose(other, np.eye(3), rtol=0, atol=1e-9)  # Rec.709's own: another entry, not the first
