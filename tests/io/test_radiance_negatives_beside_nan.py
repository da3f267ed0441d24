"""Radiance HDR holds neither negative values nor NaN: an image that holds both gets both notes. A single NaN
must not hide the negatives (their note was dropped whenever the image also held a NaN or an infinity).

Outside values: a PFM made here with NumPy (one NaN, two negatives of known value), and OpenEXR's
AllHalfValues.exr, every half bit pattern, read by OpenEXR's own binding and its finite negatives counted
with NumPy (the infinities have the writer's non-finite note)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main


def _notes(err: str, word: str) -> list[str]:
    return [line for line in err.splitlines() if word in line]


def test_a_nan_does_not_hide_the_negatives(tmp_path, capsys):
    image = np.ones((4, 5, 3), "<f4")
    image[0, 0, 0] = np.nan
    image[1, 2, 1] = -0.5
    image[3, 4, 2] = -2.0
    src = tmp_path / "in.pfm"
    src.write_bytes(b"PF\n5 4\n-1.0\n" + image[::-1].tobytes())  # rows bottom to top, little-endian
    assert main(["convert", str(src), "-o", str(tmp_path / "out.hdr")]) == 0
    err = capsys.readouterr().err
    assert _notes(err, "negative") == [
        f"lenslab convert: note: {src}: Radiance HDR holds no negative values: 2 negative values, down to -2, set to 0 "
        "(of 60 values)"]
    assert len(_notes(err, "1 NaN")) == 1  # and the NaN's own note


OpenEXR = pytest.importorskip("OpenEXR")


def test_every_half_value_written_as_rgbe_counts_its_negatives(tmp_path, capsys, shared_data):
    path = shared_data / "formats/openexr-images/TestImages/AllHalfValues.exr"
    values = OpenEXR.File(str(path)).channels()["RGB"].pixels.astype(np.float64)
    finite = np.isfinite(values)
    negative = (values < 0) & finite
    assert np.count_nonzero(~finite) == 3 * (2046 + 2)  # 2046 NaN patterns and 2 infinities per channel
    assert main(["convert", str(path), "-o", str(tmp_path / "out.hdr")]) == 0
    assert _notes(capsys.readouterr().err, "negative") == [
        f"lenslab convert: note: {path}: Radiance HDR holds no negative values: {np.count_nonzero(negative)} negative "
        f"values, down to {values[negative].min():.2g}, set to 0 (of {values.size} values)"]
