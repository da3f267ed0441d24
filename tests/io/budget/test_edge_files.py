"""The files ``lenslab bench memory`` measures at the budget's ratio edge (lenslab.bench.bombs.write_ratio_edge):
each is exactly the size asked, is the size its format's outside reader sees (OpenImageIO for EXR and JPEG,
PyAV, FFmpeg's HEIF demuxer, for HEIC), and declares the largest 2:1 image that a file of its size may
decode to by the formula max(96 MiB, 512 * b) for b <= 1 MiB, transcribed here: the budget admits it, and
the next 2:1 size would pass the formula."""

from __future__ import annotations

import pytest

from lenslab.bench.bombs import EDGE_FORMATS, write_ratio_edge
from lenslab.io.budget import admit
from lenslab.io.registry import get

pytest.importorskip("OpenImageIO")
from tests.io.test_decompression_bombs import _outside_size  # noqa: E402  (OpenImageIO; PyAV for HEIC)


@pytest.mark.parametrize("fmt", sorted(EDGE_FORMATS))
def test_a_half_mib_file_at_the_ratio_edge(tmp_path, fmt):
    size = 512 << 10
    budget = 512 * size  # 268 MB: over the 96 MiB base
    channels, ext = EDGE_FORMATS[fmt]
    path = tmp_path / f"edge{ext}"
    w, h = write_ratio_edge(path, size, fmt)
    assert path.stat().st_size == size
    assert _outside_size(path) == (w, h) and w == 2 * h
    assert w * h * channels * 4 <= budget < (w + 2) * (h + 1) * channels * 4
    declared = admit(path, get(fmt))  # admitted: no BudgetError
    assert (declared.width, declared.height) == (w, h)
