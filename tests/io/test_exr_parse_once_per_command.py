"""A command parses each EXR input's header once: the channel check that ``warp``, ``tonemap`` and ``convert``
make before their job (can the output format hold these channels?) and the job's read take the same parse,
kept for the file it was read from. Expected values: OpenEXR's reading of the same header."""

from __future__ import annotations

import os
from collections import Counter

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io.exr import chunks


def _exr(path, channels="RGB", size=(24, 12)):
    w, h = size
    rng = np.random.default_rng(3)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {c: rng.random((h, w)).astype(np.float32) for c in channels}).write(str(path))
    return path


@pytest.fixture
def parses(monkeypatch):
    """The headers lenslab's parser really reads (not answers it kept), by file."""
    calls = Counter()
    headers = chunks._headers

    def counted(f, size):
        calls[os.path.abspath(f.name)] += 1
        return headers(f, size)

    monkeypatch.setattr(chunks, "_headers", counted)
    return calls


def _openexr_channels(path):
    return [c.name for c in OpenEXR.File(str(path), header_only=True).parts[0].header["channels"]]


@pytest.mark.parametrize("args", [
    ["warp", "--from", "equirect", "--to", "fisheye:fov=180", "--size", "16x16"],
    ["tonemap", "--curve", "reinhard"],
    ["convert", "--to", "png"],
], ids=["warp", "tonemap", "convert"])
def test_each_input_header_is_parsed_once_per_command(tmp_path, parses, args):
    inputs = [_exr(tmp_path / f"in{i}.exr", channels="RGBA" if i else "RGB") for i in range(2)]
    for src in inputs:
        out = tmp_path / f"{src.stem}_out.{'exr' if args[0] == 'warp' else 'png'}"
        assert main([args[0], str(src), *args[1:], "-o", str(out), "-q"]) == 0
        assert out.exists()
    assert {p: parses[str(p)] for p in inputs} == {p: 1 for p in inputs}
    for src in inputs:  # the kept parse is OpenEXR's header
        layout = chunks.parse_header(src)
        assert layout.parts[0]["channel_names"] == _openexr_channels(src)
        assert chunks.first_part_channels(src) == _openexr_channels(src)
    assert {p: parses[str(p)] for p in inputs} == {p: 1 for p in inputs}  # still the one parse


def test_a_file_written_again_is_parsed_again(tmp_path, parses):
    path = _exr(tmp_path / "f.exr", channels="RGB")
    assert chunks.first_part_channels(path) == _openexr_channels(path) == ["B", "G", "R"]
    _exr(tmp_path / "g.exr", channels="RGBA", size=(30, 20))
    os.replace(tmp_path / "g.exr", path)  # another file at the same path
    assert chunks.first_part_channels(path) == _openexr_channels(path) == ["A", "B", "G", "R"]
    x0, y0, x1, y1 = chunks.parse_header(path).parts[0]["dataWindow"]
    dw = OpenEXR.File(str(path), header_only=True).parts[0].header["dataWindow"]
    assert (x0, y0, x1, y1) == tuple(int(v) for corner in dw for v in corner) == (0, 0, 29, 19)
    assert parses[str(path)] == 2
