"""lenslab info: every EXR part and channel with its pixel type, sampling and compression (as OpenEXR wrote
them in the test), TIFF pages (as tifffile wrote them), the Ultra HDR note, and the format table."""

from __future__ import annotations

import json

import numpy as np
import OpenEXR
import tifffile

from lenslab.cli.main import main


def _info(capsys, *argv) -> list:
    assert main(["info", "--json", *argv]) == 0
    return json.loads(capsys.readouterr().out)


def test_exr_parts_channels_types_and_compression(tmp_path, capsys):
    h, w = 4, 6
    rgb = {c: np.full((h, w), i + 1, np.float16) for i, c in enumerate("RGB")}
    depth = {"Z": np.full((h, w), 7.0, np.float32), "mask.id": np.full((h, w), 3, np.uint32)}
    parts = [OpenEXR.Part({"compression": OpenEXR.PIZ_COMPRESSION, "type": OpenEXR.scanlineimage}, rgb, "beauty"),
             OpenEXR.Part({"compression": OpenEXR.ZIPS_COMPRESSION, "type": OpenEXR.scanlineimage}, depth, "aux")]
    OpenEXR.File(parts).write(str(tmp_path / "m.exr"))
    (d,) = _info(capsys, str(tmp_path / "m.exr"))
    ps = d["structure"]["parts"]
    assert [p["name"] for p in ps] == ["beauty", "aux"]
    assert [p["compression"] for p in ps] == ["piz", "zips"]
    types = {c["name"]: c["type"] for p in ps for c in p["channels"]}
    assert types == {"R": "half", "G": "half", "B": "half", "Z": "float", "mask.id": "uint"}
    assert ps[1]["layers"] == ["mask"]
    assert ps[0]["data_window"] == [0, 0, w - 1, h - 1] == ps[0]["display_window"]


def test_subsampled_chroma_from_the_shared_files(shared_data, capsys):
    (d,) = _info(capsys, str(shared_data / "formats/openexr-images/Chromaticities/Rec709_YC.exr"))
    chans = {c["name"]: c["sampling"] for c in d["structure"]["parts"][0]["channels"]}
    assert chans == {"Y": [1, 1], "RY": [2, 2], "BY": [2, 2]}  # the file's 2x2-subsampled chroma (MANIFEST)
    (m,) = _info(capsys, str(shared_data / "formats/openexr-images/Beachball/multipart.0001.exr"))
    assert len(m["structure"]["parts"]) == 10  # MULTIPART with 10 parts (MANIFEST)


def test_tiff_pages_and_ultrahdr_note(tmp_path, shared_data, capsys):
    with tifffile.TiffWriter(tmp_path / "p.tif") as t:
        t.write(np.zeros((3, 5, 3), np.float32), photometric="rgb", compression="zlib")
        t.write(np.zeros((2, 2), np.uint16))
    (d,) = _info(capsys, str(tmp_path / "p.tif"))
    pages = d["structure"]["pages"]
    assert [p["dtype"] for p in pages] == ["float32", "uint16"] and pages[0]["shape"] == [3, 5, 3]
    (u,) = _info(capsys, str(shared_data / "formats/oiio-images/ultrahdr_sky.jpg"))
    assert u["attributes"]["rendition"].startswith("HDR")  # the gain map applied (2.205275 stops, its XMP)
    assert "GainMapMax 2.205 (log2)" in u["attributes"]["gain_map"] and u["stats"][1]["max"] > 4.0


def test_format_table(capsys):
    rows = _info(capsys, "--formats")
    names = [r["name"] for r in rows]
    for name in ("exr", "hdr", "tiff", "pfm", "png", "jpg"):
        assert name in names
    hdr = rows[names.index("hdr")]
    assert hdr["hdr"] and not hdr["alpha"] and ".hdr" in hdr["extensions"]
    assert main(["info"]) == 2  # no file and no --formats: a usage error
