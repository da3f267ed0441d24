"""A lens argument that names a file (``--to``, ``--from``, ``--source``, tracer's ``--camera``, ``camera show``)
is read as that file, whatever its extension:

- a file that is not there is said so, as a missing input image is (``lenslab warp missing.exr``: exit 1,
  ``FILE: no such file or directory``, the operating system's words for ENOENT), never "unknown lens model";
- an image that records no camera cannot be a lens: a usage mistake (exit 2), one line that says the file
  records no camera and what to give instead (a lens spec or a calibration file).
"""

from __future__ import annotations

import errno
import os

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from tracer.cli import main as tracer

oiio = pytest.importorskip("OpenImageIO")

#: what the operating system says of a name that is not there (strerror(ENOENT)), as the error lines say it
ENOENT = os.strerror(errno.ENOENT).lower()


def plain_exr(path):
    """An EXR written by OpenImageIO: a real image with no lenslab camera in its header."""
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(16, 8, 3, oiio.HALF))
    out.write_image(np.ones((8, 16, 3), np.float32))
    out.close()
    return path


def commands(src, lens):
    """Every command line that takes ``lens`` where a camera is expected."""
    return [
        (lenslab, ["warp", str(src), "--to", lens, "-o", "y.exr", "-q"]),
        (lenslab, ["warp", str(src), "--from", lens, "--to", "perspective:fov=60", "-o", "y.exr", "-q"]),
        (lenslab, ["stmap", "--from", lens, "--to", "perspective", "--size", "16x16", "-o", "m.exr", "-q"]),
        (lenslab, ["stmap", "--from", "perspective", "--to", lens, "--size", "16x16", "-o", "m.exr", "-q"]),
        (lenslab, ["fit", "lens", "--from", lens, "--model", "brown", "--size", "16x16"]),
        (lenslab, ["camera", "show", lens]),
        (lenslab, ["camera", "convert", lens, "-o", "c.yaml"]),
        (tracer, ["render", "--scene", "furnace", "--camera", lens, "--size", "16x8", "--spp", "1", "-q",
                  "-o", "r.exr"]),
    ]


def run(main, argv, capsys) -> tuple[int, list[str]]:
    capsys.readouterr()
    code = main(argv)
    return code, capsys.readouterr().err.strip().splitlines()


@pytest.fixture
def pano(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    src = tmp_path / "pano.exr"
    plain_exr(src)  # (2:1: an equirect for warp without --from)
    return src


def test_a_missing_input_image_is_a_failed_input(pano, capsys):
    # the convention the lens files follow: lenslab warp of an image that is not there
    code, err = run(lenslab, ["warp", "missing_in.exr", "--to", "perspective", "-o", "y.exr"], capsys)
    assert (code, err) == (1, [f"lenslab warp: error: missing_in.exr: {ENOENT}"])


@pytest.mark.parametrize("i", range(len(commands("p", "x"))))
@pytest.mark.parametrize("name", ["missing.exr", "dir/missing.png", "missing.yaml"])
def test_a_missing_lens_file_is_said_missing(pano, capsys, i, name):
    main, argv = commands(pano, name)[i]
    code, err = run(main, argv, capsys)
    assert code == 1 and len(err) == 1, err
    assert err[0].endswith(f"{name}: {ENOENT}"), err
    assert "unknown lens model" not in err[0]
    assert not any(p.name in ("y.exr", "m.exr", "c.yaml", "r.exr") for p in pano.parent.iterdir())


@pytest.mark.parametrize("i", range(len(commands("p", "x"))))
def test_an_image_without_a_camera_is_a_usage_mistake(pano, capsys, i):
    forest = plain_exr(pano.parent / "forest.exr")
    main, argv = commands(pano, str(forest))[i]
    code, err = run(main, argv, capsys)
    assert code == 2 and len(err) == 1, err
    assert f"{forest}: this OpenEXR image records no camera" in err[0], err
    assert "give a lens spec" in err[0] and "or a calibration file" in err[0], err
    assert str(pano) not in err[0]  # the lens argument's fault, not the input's
