"""A warp by an ST map reads a source's NaN as 0 and its +-inf as the largest float32, and says so in one note, as a
lens-to-lens warp does: it wrote them into the output as NaN and inf, silently.

Outside value: through the identity map (each output pixel centre reads its own centre: ``s = (x + 1/2) / W``,
``t = 1 - (y + 1/2) / H``, written out here) the output is NumPy's ``nan_to_num`` of the source, NaN -> 0,
+-inf -> +-3.4028235e38 (``numpy.finfo(numpy.float32).max``)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.stmap import write_st_map

W, H = 24, 12
BIG = np.finfo(np.float32).max


def _files(tmp_path):
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    src = np.stack([1.0 + x / W, 2.0 + y / H, 0.5 + 0 * x], axis=-1).astype(np.float32)
    src[2, 3, 0], src[5, 7, 1], src[8, 20, 2] = np.nan, np.inf, -np.inf
    write(tmp_path / "src.exr", src, pixel_type="float")
    st = np.zeros((H, W, 4), np.float32)
    st[..., 0], st[..., 1], st[..., 3] = (x + 0.5) / W, 1.0 - (y + 0.5) / H, 1.0
    write_st_map(tmp_path / "map.exr", st)
    return src


@pytest.mark.parametrize("flags", [[], ["--samples", "4"], ["--antialias"]])
def test_stmap_warp_reads_non_finite_source_values_as_finite(tmp_path, capsys, flags):
    src = _files(tmp_path)
    out = tmp_path / "out.exr"
    assert main(["warp", str(tmp_path / "src.exr"), "--stmap", str(tmp_path / "map.exr"), "-o", str(out),
                 "--pixel-type", "float", "--no-alpha", *flags]) == 0
    got = read(out)[0]
    assert np.isfinite(got).all()
    expected = np.nan_to_num(src, nan=0.0, posinf=BIG, neginf=-BIG)
    if not flags:  # one sample at each pixel's own centre: the pixel itself, but for the float32 rounding of a
        # map's coordinate (s W - 1/2 off by an ulp puts a weight of ~1e-7 on a neighbour)
        np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-6)
    else:  # samples and footprints spread over each pixel: the warp of NumPy's finite copy of the source, bit for bit
        write(tmp_path / "finite.exr", expected, pixel_type="float")
        assert main(["warp", str(tmp_path / "finite.exr"), "--stmap", str(tmp_path / "map.exr"), "-o",
                     str(tmp_path / "finite_out.exr"), "--pixel-type", "float", "--no-alpha", "-q", *flags]) == 0
        np.testing.assert_array_equal(got, read(tmp_path / "finite_out.exr")[0])
    assert "the source has 3 non-finite values: NaN read as 0, +-inf as the largest float32" in capsys.readouterr().err
