"""``lenslab info --formats`` (its table and its JSON) and the formats table of docs/conventions.md say which
``--pixel-type``s each format is written with; the types listed are exactly those that writing gives.

Outside values: the sample type of each written file as another library reads it (tifffile, OpenCV, OpenImageIO,
the Radiance header's FORMAT line: ``tests/jobs/test_pixel_type_outputs.py``'s readers), and the types the PNG and
OpenEXR specifications give their samples (PNG: 8 or 16-bit integers, no floats; OpenEXR: half, float, uint, of which
lenslab writes the two floats)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io.registry import formats
from tests.jobs.test_pixel_type_outputs import DTYPES, _samples, _source

ROOT = Path(__file__).resolve().parents[2]
#: every --pixel-type a user may name, written out here rather than taken from the plugins under test
EVERY_TYPE = ("uint8", "uint16", "half", "float", "rgbe")


def _listed(capsys) -> dict[str, str]:
    """Each format's ``--pixel-type`` cell of the ``lenslab info --formats`` table."""
    capsys.readouterr()
    assert main(["info", "--formats"]) == 0
    head, *rows = capsys.readouterr().out.splitlines()
    start, end = head.index("--pixel-type"), head.index("extensions")
    return {row.split()[0]: row[start:end].strip() for row in rows}


def test_the_listing_names_the_types_each_format_writes(capsys):
    listed = _listed(capsys)
    assert listed["png"] == "uint8/uint16" and "half" not in listed["png"]
    assert listed["exr"] == "half/float"
    assert listed["jpg"] == "uint8"
    assert listed["tiff"] == "uint8/uint16/half/float"
    assert listed["heif"] == "-" and listed["video"] == "-"  # read only; a clip's samples are its codec's
    assert main(["info", "--formats", "--json"]) == 0
    described = {d["name"]: d["pixel_types"] for d in json.loads(capsys.readouterr().out)}
    assert described["png"] == ["uint8", "uint16"] and described["exr"] == ["half", "float"]
    assert described == {name: ([] if cell == "-" else cell.split("/")) for name, cell in listed.items()}


def test_the_docs_table_names_them_too(capsys):
    listed = _listed(capsys)
    text = (ROOT / "docs" / "conventions.md").read_text(encoding="utf-8")
    table = text.split("<!-- formats:start -->")[1].split("<!-- formats:end -->")[0]
    rows = {line.split("`")[1]: line.split("|")[4].strip() for line in table.splitlines() if line.startswith("| `")}
    assert rows["png"] == "`uint8`, `uint16`" and rows["exr"] == "`half`, `float`"
    assert {name: cell.replace("`", "").replace(", ", "/") for name, cell in rows.items()} == listed


WRITTEN = [f.name for f in formats().values() if f.writable and f.kind == "image"]


@pytest.mark.parametrize("name", WRITTEN)
def test_the_listed_types_are_those_writing_gives(tmp_path, capsys, name):
    listed = _listed(capsys)[name].split("/")
    src = _source(tmp_path, grey=name == "pgm")
    ext = formats()[name].extensions[0]
    written = []
    for kind in EVERY_TYPE:
        out = tmp_path / f"{kind}{ext}"
        code = main(["convert", str(src), "-o", str(out), "--pixel-type", kind, "-q"])
        err = capsys.readouterr().err
        assert code in (0, 2), err  # written, or refused in one line as a usage error
        if code == 0:
            assert _samples(out) == ("rgbe" if kind == "rgbe" else np.dtype(DTYPES[kind])), kind
            written.append(kind)
        else:
            assert not out.exists() and len(err.strip().splitlines()) == 1, err
    assert written == listed  # (in the listing's order: integers by depth, then the floats)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
