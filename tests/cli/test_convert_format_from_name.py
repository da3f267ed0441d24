"""``lenslab convert IN -o NAME.EXT`` writes the format the name says, as warp and tonemap do: one output
file needs no ``--to``. A folder ``-o`` (or none) still needs ``--to``, and a ``--to`` that differs from the
name's extension is a usage error in warp's words; both found before any input is read (exit status 2, one
line). The written file is judged by OpenImageIO, a reader outside lenslab."""

from __future__ import annotations

import numpy as np
import pytest
from lenslab.cli.main import main
from lenslab.cli.convert import FORMATS, VIDEO

JUNK = b"not an image\n" * 8  # no format reads this: a command that read it would fail it (exit status 1)


def _run(capsys, argv):
    code = main(["convert", *argv])
    return code, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("name, oiio_format", [("p3.png", "png"), ("p3.jpg", "jpeg"), ("p3.jpeg", "jpeg"),
                                               ("p3.tif", "tiff"), ("p3.ppm", "pnm"), ("p3.hdr", "hdr")])
def test_one_output_file_takes_its_format_from_its_extension(tmp_path, capsys, name, oiio_format):
    import OpenImageIO as oiio

    from lenslab.io import write

    write(tmp_path / "forest.exr", np.full((6, 10, 3), 0.18, np.float32))
    code, lines = _run(capsys, [str(tmp_path / "forest.exr"), "-o", str(tmp_path / name), "-q"])
    assert code == 0, lines
    inp = oiio.ImageInput.open(str(tmp_path / name))  # OpenImageIO tells the format from the bytes it reads
    try:
        assert inp.format_name() == oiio_format and (inp.spec().width, inp.spec().height) == (10, 6)
    finally:
        inp.close()


@pytest.mark.parametrize("output", [None, "out/", "folder"])
def test_without_a_file_name_the_format_is_asked_for(tmp_path, capsys, monkeypatch, output):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "forest.exr").write_bytes(JUNK)
    (tmp_path / "folder").mkdir()
    code, lines = _run(capsys, ["forest.exr", *(["-o", output] if output else [])])
    where = "no -o" if output is None else "-o names a folder"
    assert code == 2, lines
    assert lines == [f"lenslab convert: error: say which format to write: --to FORMAT ({', '.join(FORMATS + VIDEO)}), "
                     f"or -o NAME.EXT for one output file ({where})"]
    assert not (tmp_path / "out").exists()


def test_a_to_that_differs_from_the_name_is_a_usage_error_as_in_warp(tmp_path, capsys):
    (tmp_path / "forest.exr").write_bytes(JUNK)
    out = tmp_path / "p3.png"
    code, lines = _run(capsys, [str(tmp_path / "forest.exr"), "--to", "jpg", "-o", str(out)])
    assert code == 2, lines
    assert lines == [f"lenslab convert: error: -o {out}: the name says png but the output format asked is jpg; "
                     "give -o NAME.jpg, or the format the name says"]
    code, warp = main(["warp", str(tmp_path / "forest.exr"), "--to", "equirect", "--format", "jpg", "-o", str(out)]), \
        capsys.readouterr().err.strip().splitlines()
    assert code == 2 and warp == [lines[0].replace("lenslab convert", "lenslab warp")]  # one rule, one wording
    assert not out.exists()


def test_an_unknown_extension_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "forest.exr").write_bytes(JUNK)
    code, lines = _run(capsys, [str(tmp_path / "forest.exr"), "-o", str(tmp_path / "p3.xyz")])
    assert code == 2 and len(lines) == 1 and "cannot tell the output format from the extension '.xyz'" in lines[0]
