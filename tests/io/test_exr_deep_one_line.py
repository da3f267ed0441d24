"""A multi-part EXR whose first part is deep (``v2/Stereo/Trunks.exr``) is read as any multi-part file is:
part 0 flattened, with one note that names the other part and how to pick it; a selected part reads without
the note. Expected values: OpenImageIO's reading of the file (two subimages, both deep, named as the
note names them)."""

from __future__ import annotations

import subprocess
import sys

import pytest

oiio = pytest.importorskip("OpenImageIO")


@pytest.mark.parametrize("command", [["convert", "--to", "exr"], ["tonemap"]])
def test_a_deep_first_part_is_read_with_one_note(shared_data, tmp_path, command):
    src = shared_data / "formats" / "openexr-images" / "v2" / "Stereo" / "Trunks.exr"
    inp = oiio.ImageInput.open(str(src))
    names = [inp.spec().getattribute("name")]
    assert inp.spec().deep and inp.seek_subimage(1, 0) and inp.spec().deep and not inp.seek_subimage(2, 0)
    inp.seek_subimage(1, 0)
    names.append(inp.spec().getattribute("name"))
    inp.close()
    out = tmp_path / ("o.exr" if command[0] == "convert" else "o.png")
    run = subprocess.run([sys.executable, "-m", "lenslab", command[0], str(src), *command[1:], "-o", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if "parts" in line]
    assert notes == [f"lenslab {command[0]}: note: {src}: has 2 parts (0: '{names[0]}', 1: '{names[1]}'); read part 0 "
                     f"('{names[0]}') only: the other part is neither read nor written; pick another as "
                     "Trunks.exr:NAME or Trunks.exr:INDEX"], run.stderr
    assert out.is_file()
    picked = subprocess.run([sys.executable, "-m", "lenslab", command[0], f"{src}:{names[1]}", *command[1:], "-o",
                             str(tmp_path / ("p" + out.suffix))], capture_output=True, text=True)
    assert picked.returncode == 0 and "parts" not in picked.stderr, picked.stderr
