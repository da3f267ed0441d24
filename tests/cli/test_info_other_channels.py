"""``lenslab info`` names every channel of the part beside the image's (a render's depth, disparity and
motion layers, another view), as OpenImageIO lists the part's channels; convert to EXR keeps the same."""

from __future__ import annotations

import json

import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")


def oiio_channels(path) -> list[str]:
    inp = oiio.ImageInput.open(str(path))
    try:
        return list(inp.spec().channelnames)
    finally:
        inp.close()


@pytest.fixture
def singlepart(shared_data):
    return shared_data / "formats" / "openexr-images" / "Beachball" / "singlepart.0001.exr"


def test_info_lists_every_other_channel_with_its_count(singlepart, capsys):
    others = [n for n in oiio_channels(singlepart) if n not in ("R", "G", "B", "A")]
    assert len(others) == 16  # Z, disparity, forward motion, the left view, the white-bar masks
    assert main(["info", "--json", str(singlepart)]) == 0
    described = json.loads(capsys.readouterr().out)[0]
    assert sorted(described["extra_channels"]) == sorted(others)
    assert main(["info", str(singlepart)]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "other channel" in ln)
    assert line.strip().startswith("16 other channel(s)") and line.endswith("and 4 more")
    assert "Z, disparityL.x" in line and "not read" not in line


def test_convert_to_exr_keeps_what_info_lists(singlepart, tmp_path, capsys):
    assert main(["info", "--json", str(singlepart)]) == 0
    listed = json.loads(capsys.readouterr().out)[0]["extra_channels"]
    out = tmp_path / "s.exr"
    assert main(["convert", str(singlepart), "--to", "exr", "-o", str(out), "-q"]) == 0
    assert sorted(oiio_channels(out)) == sorted(["R", "G", "B", "A", *listed]) == sorted(oiio_channels(singlepart))


def test_a_view_read_alone_says_which_channels_of_the_other_views_it_leaves_out(shared_data, tmp_path, capsys):
    src = shared_data / "formats" / "openexr-images" / "MultiView" / "Adjuster.exr"
    names = oiio_channels(src)
    assert {"R", "left.R", "right.R"} <= set(names)  # base (centre), left and right views
    assert main(["info", f"{src}:left"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "other views" in ln)
    assert "view left alone: 6 channel(s) of the other views not read: B, G, R, right.B, right.G, right.R" in line
    out = tmp_path / "left.exr"
    assert main(["convert", f"{src}:left", "--to", "exr", "-o", str(out)]) == 0
    note = [ln for ln in capsys.readouterr().err.splitlines() if "not written" in ln]
    assert len(note) == 1 and "'B', 'G', 'R', 'right.B', 'right.G', 'right.R' not written" in note[0]
    assert sorted(oiio_channels(out)) == ["B", "G", "R"]  # the left view alone, as a plain image
