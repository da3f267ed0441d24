"""``lenslab info`` says each thing once, and names parts and inputs as users read them:

- a multi-part EXR: its parts are listed (and which one the statistics are of), without convert's "read part 0
  only" note; an Ultra HDR JPEG's gain map is mentioned once, not as a note and again as a line;
- a part without a name is ``part 0 (unnamed)``, in info's listing and in the errors that list parts, never
  ``('')``;
- ``lenslab tonemap Trunks.exr:left``'s notes name the input as typed, with its selector, as warp's and
  convert's do.

Expected names come from OpenEXR itself (the parts of files it wrote or reads).
"""

from __future__ import annotations

import contextlib
import io
import re

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")


def _run(argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _openexr_part_names(path) -> list[str]:
    return [p.name() for p in OpenEXR.File(str(path)).parts]


def _two_parts(path):
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    a = np.full((4, 8), 0.5, np.float32)
    OpenEXR.File([OpenEXR.Part({**h, "name": "beauty"}, {"R": a, "G": a, "B": a}, "beauty"),
                  OpenEXR.Part({**h, "name": "depth"}, {"Z": 7 * a}, "depth")]).write(str(path))
    return path


def _one_unnamed_part(path):
    """A single-part file (no part name, as OpenEXR writes one) with a layer 'left' and a depth channel."""
    a = np.full((4, 8), 0.25, np.float32)
    channels = {c: a for c in ("R", "G", "B", "left.R", "left.G", "left.B", "Z")}
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, channels).write(str(path))
    return path


def _check_parts_listed_without_note(path):
    names = _openexr_part_names(path)
    code, out, err = _run(["info", str(path)])
    assert code == 0
    assert err == ""  # no "read part 0 only" note: info lists the parts itself
    listed = re.findall(r"^  part (\d+) \((.*?)\): ", out, flags=re.M)
    assert listed == [(str(i), n) for i, n in enumerate(names)]
    assert f"  statistics of part 0 ({names[0]}) of the {len(names)} listed below" in out


def test_info_lists_the_parts_of_a_multi_part_file_without_the_note(tmp_path):
    _check_parts_listed_without_note(_two_parts(tmp_path / "m.exr"))


def test_info_on_the_real_multi_part_file(shared_data):
    path = shared_data / "formats" / "openexr-images" / "Beachball" / "multipart.0001.exr"
    assert len(_openexr_part_names(path)) == 10
    _check_parts_listed_without_note(path)


def test_a_selector_says_which_part_the_statistics_are_of(tmp_path):
    path = _two_parts(tmp_path / "m.exr")
    code, out, err = _run(["info", f"{path}:depth"])
    assert code == 0 and err == ""
    assert "  statistics of part 1 (depth) of the 2 listed below" in out


def _ultra_hdr_jpeg(path):
    """A JPEG carrying an Ultra HDR XMP packet (the ``hdrgm`` namespace of Adobe's gain map specification) in an
    APP1 segment after SOI; its pixels are an ordinary JPEG's."""
    ok, data = cv2.imencode(".jpg", np.full((8, 8, 3), 128, np.uint8))
    assert ok
    xmp = (b"http://ns.adobe.com/xap/1.0/\x00<x:xmpmeta xmlns:x='adobe:ns:meta/'><rdf:RDF xmlns:rdf="
           b"'http://www.w3.org/1999/02/22-rdf-syntax-ns#'><rdf:Description xmlns:hdrgm='http://ns.adobe.com/"
           b"hdr-gain-map/1.0/' hdrgm:Version='1.0'/></rdf:RDF></x:xmpmeta>")
    segment = b"\xff\xe1" + (len(xmp) + 2).to_bytes(2, "big") + xmp
    data = data.tobytes()
    path.write_bytes(data[:2] + segment + data[2:])
    return path


def _gain_map_mentions(path) -> int:
    code, out, err = _run(["info", str(path)])
    assert code == 0
    return (out + err).lower().count("gain map")


def test_a_gain_map_is_mentioned_once(tmp_path):
    assert _gain_map_mentions(_ultra_hdr_jpeg(tmp_path / "sky.jpg")) == 1


def test_the_real_ultra_hdr_jpeg_mentions_its_gain_map_once(shared_data):
    assert _gain_map_mentions(shared_data / "formats" / "oiio-images" / "ultrahdr_sky.jpg") == 1


def test_an_unnamed_part_is_listed_as_unnamed(tmp_path):
    path = _one_unnamed_part(tmp_path / "one.exr")
    assert _openexr_part_names(path) == [""]  # OpenEXR: a single-part file's part has no name
    code, out, _ = _run(["info", str(path)])
    assert code == 0
    assert re.findall(r"^  part .*?: ", out, flags=re.M) == ["  part 0 (unnamed): "]


@pytest.mark.parametrize("selector, said", [("3", "part 3 does not exist; the file has 1 part(s) (0: unnamed)"),
                                            ("bogus", "no part, layer or view named 'bogus'; parts: 0: unnamed;")])
def test_errors_list_an_unnamed_part_as_unnamed(tmp_path, selector, said):
    path = _one_unnamed_part(tmp_path / "one.exr")
    code, _, err = _run(["info", f"{path}:{selector}"])
    assert code == 1
    assert said in err and "''" not in err


def _dropped_notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "not written" in line]


def test_tonemap_names_the_input_as_typed(tmp_path):
    """The same note from tonemap, convert and warp, each naming ``one.exr:left``."""
    typed = f"{_one_unnamed_part(tmp_path / 'one.exr')}:left"
    runs = {"tonemap": ["tonemap", typed, "-o", str(tmp_path / "t.png"), "-q"],
            "convert": ["convert", typed, "--to", "png", "-o", str(tmp_path / "c.png"), "-q"],
            "warp": ["warp", typed, "--from", "perspective:fov=40", "--to", "equirect", "--size", "8x4",
                     "-o", str(tmp_path / "w.png"), "-q"]}
    for command, argv in runs.items():
        code, _, err = _run(argv)
        assert code == 0, err
        notes = _dropped_notes(err)
        assert len(notes) == 1 and notes[0].startswith(f"lenslab {command}: note: {typed}: channel(s) "), err


def test_tonemap_of_the_real_trunks_left_names_it(tmp_path, shared_data):
    typed = f"{shared_data / 'formats' / 'openexr-images' / 'v2' / 'Stereo' / 'Trunks.exr'}:left"
    code, _, err = _run(["tonemap", typed, "-o", str(tmp_path / "t.png"), "-q"])
    assert code == 0
    assert _dropped_notes(err) == [f"lenslab tonemap: note: {typed}: channel(s) 'Z' not written: a tone-mapped image "
                                   "holds display colour and alpha only (keep depth, normals and vectors with "
                                   "lenslab convert --to exr)"]
