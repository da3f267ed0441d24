"""``lenslab info --formats``: a table whose columns line up, every row's extensions starting where the
header's ``extensions`` does, however long a format's ``holds`` text (HEIF's 8/10/12-bit) is."""

from __future__ import annotations

from lenslab.cli.info import formats_text
from lenslab.io.registry import formats


def test_columns_line_up():
    lines = formats_text().splitlines()
    col = lines[0].index("extensions")
    notes = lines[0].index("notes")
    for line, f in zip(lines[1:], formats().values()):
        assert line[col:].startswith(f.extensions[0]) and line[col - 1] == " ", line
        assert line.ljust(notes + 1)[notes - 1:] == " " + (f.note or " "), line
