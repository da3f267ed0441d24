"""EXR to EXR keeps the header attributes that still describe the written channels (multiView when every
view's channels are written, a part's view, the shot's comments) and leaves out the ones that no longer
hold; a multi-part input says in its one note line that the other parts are not written. The values
expected are OpenImageIO's and OpenEXR's reading of the input."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")
OpenEXR = pytest.importorskip("OpenEXR")


def spec(path):
    inp = oiio.ImageInput.open(str(path))
    try:
        return inp.spec()
    finally:
        inp.close()


def header(path, part=0) -> dict:
    return OpenEXR.File(str(path), header_only=True).parts[part].header


@pytest.fixture
def exr_images(shared_data):
    return shared_data / "formats" / "openexr-images"


@pytest.mark.parametrize("name", ["MultiView/Adjuster.exr", "Beachball/singlepart.0001.exr"])
def test_multi_view_files_keep_their_views(exr_images, tmp_path, name):
    src, out = exr_images / name, tmp_path / "out.exr"
    assert main(["convert", str(src), "--to", "exr", "-o", str(out), "-q"]) == 0
    want, got = spec(src), spec(out)
    assert want.getattribute("multiView")  # ('center', 'left', 'right') / ('right', 'left')
    assert got.getattribute("multiView") == want.getattribute("multiView")
    assert sorted(got.channelnames) == sorted(want.channelnames)  # every view's channels, by name
    for attr in ("ImageDescription", "PixelAspectRatio", "screenWindowWidth"):
        assert got.getattribute(attr) == want.getattribute(attr), attr


def test_a_view_read_alone_drops_multi_view_and_keeps_the_rest(exr_images, tmp_path):
    src, out = exr_images / "MultiView/Adjuster.exr", tmp_path / "left.exr"
    assert main(["convert", f"{src}:left", "--to", "exr", "-o", str(out), "-q"]) == 0
    got = spec(out)
    assert got.getattribute("multiView") is None  # left's R, G, B are now the base channels
    assert got.getattribute("ImageDescription") == spec(src).getattribute("ImageDescription") == \
        "Plane blade adjustment mechanism"


def test_primaries_converted_to_rec709_drop_the_chromaticities(exr_images, tmp_path):
    src, out = exr_images / "Chromaticities/XYZ_YC.exr", tmp_path / "rgb.exr"
    assert main(["convert", str(src), "--to", "exr", "-o", str(out), "-q"]) == 0
    assert np.allclose(header(src)["chromaticities"][:2], (1, 0))  # CIE XYZ primaries in the input
    assert "chromaticities" not in header(out)  # the pixels are Rec.709 now: OpenEXR's default
    assert header(out)["owner"] == header(src)["owner"]


@pytest.mark.parametrize("primaries, kept", [
    ((0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290), True),  # Rec.709: the pixels stay as stored
    ((0.68, 0.32, 0.265, 0.69, 0.15, 0.06, 0.3127, 0.329), False),  # P3-D65: read into Rec.709
])
def test_chromaticities_are_kept_only_while_they_describe_the_pixels(tmp_path, primaries, kept):
    src, out = tmp_path / "in.exr", tmp_path / "out.exr"
    rgb = np.full((4, 6), 0.5, np.float16)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
                  "chromaticities": primaries, "owner": "lenslab test"}, {"R": rgb, "G": 0 * rgb, "B": rgb}).write(str(src))
    assert main(["convert", str(src), "--to", "exr", "-o", str(out), "-q"]) == 0
    assert ("chromaticities" in header(out)) is kept and header(out)["owner"] == "lenslab test"
    if kept:
        np.testing.assert_allclose(header(out)["chromaticities"], primaries, rtol=1e-6)  # float32 attribute


def test_multipart_note_says_the_other_parts_are_not_written(exr_images, tmp_path, capsys):
    src, out = exr_images / "Beachball/multipart.0001.exr", tmp_path / "m.exr"
    assert main(["convert", str(src), "--to", "exr", "-o", str(out)]) == 0
    notes = [ln for ln in capsys.readouterr().err.splitlines() if "parts" in ln]
    assert len(notes) == 1
    assert spec(src).getattribute("oiio:subimages") == 10 and oiio.ImageBuf(str(src)).nsubimages == 10
    assert "the other 9 parts are neither read nor written" in notes[0]
    assert "1: 'depth_left'" in notes[0] and "2 more" in notes[0]
    assert oiio.ImageBuf(str(out)).nsubimages == 1
    assert header(out)["view"] == header(src, 0)["view"] == "right"  # part 0's view: still its channels'
