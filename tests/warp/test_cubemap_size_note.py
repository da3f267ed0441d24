"""A cube map at a size off its layout's aspect (a 3x2 map at 100x100) has faces that are not square, or not of
whole pixels. ``lenslab warp --to``, ``lenslab stmap --to`` and ``tracer render --camera`` make it at the size
asked and say so in one and the same note; at a size with square whole faces, nothing is said; and the default
sizes are the layout's own (square faces)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import write
from tracer.cli import main as tracer


def exr_size(path) -> tuple[int, int]:
    """Width and height from the file's data window, read by OpenEXR (not by lenslab)."""
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


@pytest.fixture
def pano(tmp_path):
    p = tmp_path / "pano.exr"
    write(p, np.full((32, 64, 3), 0.5, np.float32))
    return p


def run(main, argv, capsys) -> tuple[int, list[str]]:
    code = main(argv)
    return code, capsys.readouterr().err.strip().splitlines()


def notes(lines: list[str], prog: str) -> list[str]:
    return [line.split(": note: ", 1)[1] for line in lines if line.startswith(f"{prog}: note: ")]


def commands(pano, tmp_path, spec: str, size: str):
    return {
        "lenslab warp": (lenslab, ["warp", str(pano), "--to", spec, "--size", size, "-o", str(tmp_path / "w.exr"),
                                   "-q", "--overwrite"], tmp_path / "w.exr"),
        "lenslab stmap": (lenslab, ["stmap", "--from", "equirect", "--source-size", "64x32", "--to", spec, "--size",
                                    size, "-o", str(tmp_path / "s.exr"), "--overwrite"], tmp_path / "s.exr"),
        "tracer render": (tracer, ["render", "--scene", "sky", "--camera", spec, "--size", size, "--spp", "1", "-q",
                                   "-o", str(tmp_path / "t.exr"), "--overwrite"], tmp_path / "t.exr"),
    }


@pytest.mark.parametrize("spec, size, faces", [
    ("cubemap", "100x100", "33.3333x50"),  # 100 / 3 and 100 / 2: stretched, and not whole
    ("cubemap", "101x67", "33.6667x33.5"),  # square to a pixel, but not whole pixels
    ("cubemap:layout=6x1", "120x40", "20x40"),  # whole pixels, not square
])
def test_every_command_makes_the_size_asked_with_one_note(pano, tmp_path, capsys, spec, size, faces):
    w, h = map(int, size.split("x"))
    said = {}
    for prog, (main, argv, out) in commands(pano, tmp_path, spec, size).items():
        code, err = run(main, argv, capsys)
        assert code == 0, err
        said[prog] = notes(err, prog)
        assert len(said[prog]) == 1, err
        assert exr_size(out) == (w, h)
    assert len(set(map(tuple, said.values()))) == 1  # the same words in every command
    note = said["lenslab warp"][0]
    assert f"at {size} has faces of {faces} pixels" in note and f"made at {size} as asked" in note, note


@pytest.mark.parametrize("spec, size", [("cubemap", "96x64"), ("cubemap:layout=6x1", "192x32"),
                                        ("cubemap:layout=1x6", "16x96"), ("cubemap:layout=4x3", "64x48")])
def test_square_whole_faces_get_no_note(pano, tmp_path, capsys, spec, size):
    for prog, (main, argv, out) in commands(pano, tmp_path, spec, size).items():
        code, err = run(main, argv, capsys)
        assert code == 0 and notes(err, prog) == [], err


@pytest.mark.parametrize("spec, want", [("cubemap", (48, 32)), ("cubemap:layout=6x1", (96, 16)),
                                        ("cubemap:layout=1x6", (16, 96)), ("cubemap:layout=4x3", (64, 48))])
def test_warp_defaults_to_square_faces_of_the_layout(pano, tmp_path, capsys, spec, want):
    """The default faces are 16 pixels in every layout: the source's 32 rows span 180 degrees, a face 90."""
    out = tmp_path / "c.exr"
    code, err = run(lenslab, ["warp", str(pano), "--to", spec, "-o", str(out), "-q"], capsys)
    assert code == 0 and err == []
    assert exr_size(out) == want


@pytest.mark.parametrize("spec, want", [("cubemap", (768, 512)), ("cubemap:layout=6x1", (1536, 256))])
def test_tracer_defaults_to_square_faces(tmp_path, capsys, spec, want):
    """The 512x512 default's 512 rows span 180 degrees: faces of 256 in every layout (768x512 for 3x2)."""
    out = tmp_path / "t.exr"
    code, err = run(tracer, ["render", "--scene", "sky", "--camera", spec, "--spp", "1", "-q", "-o", str(out)],
                    capsys)
    assert code == 0 and err == []
    assert exr_size(out) == want
