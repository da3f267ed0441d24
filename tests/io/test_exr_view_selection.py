"""One view of a multi-view EXR (``file.exr:right``) converted to EXR is that view alone: its channels
named as a plain image's (``right.R`` -> ``R``, ``right.Z`` -> ``Z``), no other view's channels, no
``multiView`` attribute, and a note naming what was left out. Views follow OpenEXR's naming (the first
of ``multiView`` is the default view, whose channels have no view in their names). Expected values:
OpenEXR's reading of the input and of the file written."""

from __future__ import annotations

import warnings

import numpy as np
import OpenEXR
import pytest

from lenslab.io.exr.extra import DroppedChannelsWarning
from lenslab.jobs.convert import ConvertJob

H, W = 12, 17


@pytest.fixture
def stereo(tmp_path):
    rng = np.random.default_rng(8)
    chans = {}
    for prefix in ("", "right."):  # left is the default view: its channels carry no view name
        for c in "RGBA":
            chans[prefix + c] = rng.random((H, W)).astype(np.float16)
        chans[prefix + "Z"] = rng.uniform(1, 50, (H, W)).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "multiView": ["left", "right"]}
    path = tmp_path / "stereo.exr"
    OpenEXR.File(header, chans).write(str(path))
    return path


def _convert(src, out):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ConvertJob(to="exr").run(src, str(out))
    return [w.message.command_line for w in caught if issubclass(w.category, DroppedChannelsWarning)]


def _channels(path):
    return OpenEXR.File(str(path), separate_channels=True).parts[0].channels


@pytest.mark.parametrize("view,prefix,other,other_prefix", [("right", "right.", "left", ""),
                                                             ("left", "", "right", "right.")])
def test_a_view_is_written_alone_as_a_plain_image(stereo, tmp_path, view, prefix, other, other_prefix):
    out = tmp_path / f"{view}.exr"
    notes = _convert(f"{stereo}:{view}", out)
    theirs, written = _channels(stereo), _channels(out)
    assert sorted(written) == ["A", "B", "G", "R", "Z"]
    for c in written:
        assert written[c].pixels.dtype == theirs[prefix + c].pixels.dtype
        assert np.array_equal(written[c].pixels, theirs[prefix + c].pixels)
    assert "multiView" not in OpenEXR.File(str(out), header_only=True).parts[0].header
    dropped = ", ".join(repr(n) for n in theirs if n.startswith(other_prefix) and not (other_prefix == "" and "." in n))
    assert notes == [f"channel(s) {dropped} not written: they belong to the other view(s) {other}; view {view} is "
                     "written alone, as a plain image"]


def test_the_whole_file_keeps_every_view(stereo, tmp_path):
    out = tmp_path / "all.exr"
    assert _convert(str(stereo), out) == []
    assert sorted(_channels(out)) == sorted(_channels(stereo))
    assert list(OpenEXR.File(str(out), header_only=True).parts[0].header["multiView"]) == ["left", "right"]


@pytest.mark.shared_data
def test_adjuster_left_is_its_left_view_only(tmp_path, shared_data):
    adjuster = shared_data / "formats/openexr-images/MultiView/Adjuster.exr"  # R, G, B; left.*; right.*
    out = tmp_path / "left.exr"
    notes = _convert(f"{adjuster}:left", out)
    theirs, written = _channels(adjuster), _channels(out)
    assert sorted(written) == ["B", "G", "R"]
    for c in "RGB":
        assert np.array_equal(written[c].pixels, theirs[f"left.{c}"].pixels)
    assert notes == ["channel(s) 'B', 'G', 'R', 'right.B', 'right.G', 'right.R' not written: they belong to the other "
                     "view(s) center, right; view left is written alone, as a plain image"]
