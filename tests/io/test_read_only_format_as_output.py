"""An output named with the extension of a format lenslab only reads (HEIC) says so, instead of "cannot
tell the output format"; derived from the registry, so every read-only format is covered."""

from __future__ import annotations

import pytest

from lenslab.errors import FormatError
from lenslab.io.registry import format_for_path, formats

READ_ONLY = sorted(n for n, f in formats().items() if not f.writable and f.extensions and f.kind != "video")


def test_there_is_a_read_only_format():
    assert "heif" in READ_ONLY


@pytest.mark.parametrize("name", READ_ONLY)
def test_its_extensions_are_named_as_read_only(name):
    fmt = formats()[name]
    for ext in fmt.extensions:
        with pytest.raises(FormatError) as info:
            format_for_path(f"out{ext.upper()}")
        assert f"reads {fmt.title} but does not write it" in str(info.value)


def test_the_command_gives_one_usage_line(tmp_path, capsys):
    import numpy as np

    from lenslab.cli.main import main
    from lenslab.io import write

    src = tmp_path / "in.exr"
    write(src, np.zeros((4, 8, 3), np.float32))
    assert main(["convert", str(src), "-o", str(tmp_path / "out.heic")]) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1 and "reads HEIF/HEIC but does not write it" in lines[0], lines
    assert not (tmp_path / "out.heic").exists()
