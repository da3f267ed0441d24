"""The one line on slight negatives at a command's end counts files, not the images made from them, names the
file when there is one, and calls values past a codec's undershoot (2^-10) what they are.

Outside values: the count and the lowest value are NumPy's, on the input file's values (compare-tones, tonemap)
or on the float values the same warp writes to a PFM (the Lanczos warp: the PNG's tone curve is given those
values, and its note must count the same ones).
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write

cv2 = pytest.importorskip("cv2")


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "negative" in line]


def test_compare_tones_counts_its_file_once_and_names_it(tmp_path, capsys):
    image = np.full((16, 16, 3), 0.5, np.float32)
    image[3, :5, 0] = -4e-4  # a lossy codec's undershoot, within one half step at white
    path = tmp_path / "slight.pfm"
    write(path, image)
    values, _ = read(path)
    count, lowest = int(np.count_nonzero(values < 0)), float(values.min())
    assert main(["compare-tones", str(path), "-o", str(tmp_path / "strip.png")]) == 0  # three panels
    assert _notes(capsys.readouterr().err) == [
        f"lenslab compare-tones: note: {count} slightly negative values (down to {lowest:.2g}, a lossy codec's or "
        f"filter's undershoot) set to 0 in {path}"]


def test_a_lanczos_warp_says_its_lobes(tmp_path, capsys):
    image = np.zeros((64, 128, 3), np.float32)
    image[20:40, 40:80] = 4.0
    path = tmp_path / "square.pfm"
    write(path, cv2.GaussianBlur(image, (0, 0), 0.8))  # a soft edge: lobes within 3 % of their 8 x 8 block
    warp = ["warp", str(path), "--from", "equirect", "--to", "equirect", "--size", "100x50", "--filter", "lanczos"]
    assert main([*warp, "-o", str(tmp_path / "float.pfm")]) == 0
    values, _ = read(tmp_path / "float.pfm")
    count, lowest = int(np.count_nonzero(values < 0)), float(values.min())
    assert lowest < -2.0 ** -10  # past a codec's undershoot
    capsys.readouterr()
    assert main([*warp, "-o", str(tmp_path / "view.png")]) == 0
    assert _notes(capsys.readouterr().err) == [
        f"lenslab warp: note: {count} negative values from the resampling filter's lobes (down to {lowest:.2g}) "
        f"set to 0 in {path}"]


def test_block_undershoot_without_a_warp_is_the_codecs(tmp_path, capsys):
    image = np.full((16, 16, 3), 0.0, np.float32)
    image[0:8, 0:8] = 1.0
    image[2, 2, 1] = -0.01  # 1 % of its block's brightest value: a DWA block's undershoot
    path = tmp_path / "block.pfm"
    write(path, image)
    assert main(["tonemap", str(path), "-o", str(tmp_path / "out.png")]) == 0
    assert _notes(capsys.readouterr().err) == [
        f"lenslab tonemap: note: 1 negative value of a lossy codec's 8 x 8 blocks (down to -0.01, within 3.1% of "
        f"their block's brightest value) set to 0 in {path}"]
