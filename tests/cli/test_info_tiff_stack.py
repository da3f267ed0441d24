"""``lenslab info`` of a TIFF stack (a volume tifffile writes as one page per slice, a scan of many pages) describes
its first 16 pages and counts the rest in one line, instead of a line per page: the count is tifffile's own."""

from __future__ import annotations

import json

import numpy as np
import tifffile

from lenslab.cli.main import main


def test_a_stack_of_240_pages_is_16_lines_and_a_count(tmp_path, capsys):
    path = tmp_path / "stack.tif"
    tifffile.imwrite(path, np.zeros((240, 32, 2), np.float32))  # tifffile: 240 pages of 32 x 2
    with tifffile.TiffFile(path) as tif:
        total = len(tif.pages)
    assert total == 240
    assert main(["info", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert sum(line.startswith("  page ") for line in lines) == 16
    assert f"  ... and {total - 16} more page(s) (lenslab reads page 0)" in lines
    assert main(["info", "--json", str(path)]) == 0
    (d,) = json.loads(capsys.readouterr().out)
    assert d["structure"]["page_count"] == total and len(d["structure"]["pages"]) == 16


def test_a_two_page_tiff_lists_both_and_no_count(tmp_path, capsys):
    path = tmp_path / "two.tif"
    with tifffile.TiffWriter(path) as t:
        t.write(np.zeros((3, 5, 3), np.float32), photometric="rgb")
        t.write(np.zeros((2, 2), np.uint16))
    assert main(["info", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert sum(line.startswith("  page ") for line in lines) == 2
    assert not any("more page(s)" in line for line in lines)
