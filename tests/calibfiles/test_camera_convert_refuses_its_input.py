"""``lenslab camera convert`` never writes over the camera file it reads, whichever output names it: OUT or
``--residual-map``. Each is a usage error (exit 2) found from the names before the camera is read: a camera file
that could not even be read gets the same answer, and stays as it was."""

from __future__ import annotations

import os

import pytest

from lenslab.cli.main import main

#: a COLMAP cameras.txt (a SIMPLE_RADIAL camera, as COLMAP writes it)
COLMAP = "# Camera list with one line of data per camera:\n1 SIMPLE_RADIAL 640 480 500 319.5 239.5 -0.1\n"
#: what the policy says of an input named as an output (lenslab.jobs.policy.refuse_inputs), after the file name
REFUSED = ": is an input of this command; it is never written over, even with --overwrite: choose another output name"


def refusal(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("content", [COLMAP, "not a camera at all\n"], ids=["camera", "unreadable"])
def test_the_residual_map_naming_the_camera_file_is_refused_before_it_is_read(tmp_path, capsys, content):
    src = tmp_path / "cameras.txt"
    src.write_text(content)
    before = (src.read_bytes(), os.stat(src).st_mtime_ns)
    out = tmp_path / "kb.txt"
    rc = main(["camera", "convert", f"{src}#1", "-o", str(out), "--model", "kannala-brandt",
               "--residual-map", str(src), "--overwrite"])
    line = refusal(capsys)
    assert rc == 2
    assert line.endswith(f": error: {src}{REFUSED}"), line
    assert (src.read_bytes(), os.stat(src).st_mtime_ns) == before and not out.exists()


def test_the_residual_map_through_a_link_to_the_camera_file_is_refused(tmp_path, capsys):
    src = tmp_path / "cameras.txt"
    src.write_text("not a camera at all\n")
    link = tmp_path / "residual.exr"
    os.link(src, link)  # the same file under another name (device and inode)
    rc = main(["camera", "convert", str(src), "-o", str(tmp_path / "kb.txt"), "--model", "kannala-brandt",
               "--residual-map", str(link), "--overwrite"])
    assert rc == 2 and refusal(capsys).endswith(f": error: {link}{REFUSED}")
    assert src.read_text() == "not a camera at all\n"


def test_options_that_go_with_model_are_refused_before_the_camera_is_read(tmp_path, capsys):
    src = tmp_path / "cameras.txt"
    src.write_text("not a camera at all\n")
    rc = main(["camera", "convert", str(src), "-o", str(tmp_path / "out.txt"),
               "--residual-map", str(tmp_path / "r.exr")])
    assert rc == 2
    assert refusal(capsys).endswith(": error: --free, --aim and --residual-map go with --model MODEL")
