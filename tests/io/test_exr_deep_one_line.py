"""A multi-part EXR whose first part is deep (``v2/Stereo/Trunks.exr``) fails in one line: the error that
the part is deep, without the note before it that part 0 is read and the others are not (it is not
read). Expected values: OpenImageIO's reading of the file (two subimages, the first deep)."""

from __future__ import annotations

import subprocess
import sys

import pytest

oiio = pytest.importorskip("OpenImageIO")


@pytest.mark.parametrize("command", [["convert", "--to", "exr"], ["tonemap"]])
def test_a_deep_first_part_is_one_error_line(shared_data, tmp_path, command):
    src = shared_data / "formats" / "openexr-images" / "v2" / "Stereo" / "Trunks.exr"
    inp = oiio.ImageInput.open(str(src))
    assert inp.spec().deep and inp.seek_subimage(1, 0) and not inp.seek_subimage(2, 0)
    inp.close()
    out = tmp_path / "o.exr"
    run = subprocess.run([sys.executable, "-m", "lenslab", command[0], str(src), *command[1:], "-o", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 1
    lines = run.stderr.strip().splitlines()
    assert lines == [f"lenslab {command[0]}: error: {src}: part 0 ('rgba.left') is a deep image (several samples "
                     "per pixel); lenslab reads flat images only: flatten it first (e.g. with a compositor)"], lines
    assert not out.exists() and list(tmp_path.iterdir()) == []
