"""A lens argument that is a bare word naming neither a lens model nor a file (``--to missing``, ``--camera
missing``: the user may have meant either) is said to be neither, on one line, with the nearest model name when one
is close (as a misspelt option is hinted), and the models listed; exit 2. A name only a file has (a folder, an
image's extension) is still read as a file and said missing (exit 1), and a spec with parameters whose model is
unknown is still an unknown model.
"""

from __future__ import annotations

import errno
import os

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import write
from tracer.cli import main as tracer

#: the models as ``lenslab lenses`` names them, in the order the error lists them
MODELS = ("ball, barrel, brown, cubemap, cylindrical, cylindrical-equal-area, devernay-fov, distortion, division, "
          "double-sphere, dual-fisheye, eac, equirect, eucm, fb-barrel, fb-barrelsplit, fisheye, fisheye624, globe, "
          "half-equirect, hammer, kannala-brandt, lensfun, little-planet, mercator, ocam, octahedron, omnidir, opencv, "
          "opencv-fisheye, optics, pannini, perspective, pincushion, sinusoidal, stereo, swirl, tan-fisheye, "
          "tetrahedron, tiled, tsp")


@pytest.fixture
def pano(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write(tmp_path / "pano.exr", np.ones((16, 32, 3), np.float32))
    return tmp_path / "pano.exr"


def commands(lens):
    return {
        "lenslab warp --to": (lenslab, ["warp", "pano.exr", "--to", lens, "-o", "y.exr", "-q"]),
        "lenslab warp --from": (lenslab, ["warp", "pano.exr", "--from", lens, "--to", "fisheye", "-o", "y.exr", "-q"]),
        "tracer render --camera": (tracer, ["render", "--scene", "furnace", "--camera", lens, "--spp", "1", "-q",
                                            "-o", "t.exr"]),
    }


def run(capsys, main, argv):
    capsys.readouterr()
    code = main(argv)
    return code, capsys.readouterr().err


@pytest.mark.parametrize("where", list(commands("x")))
@pytest.mark.parametrize("word,hint", [("missing", ""), ("Missing", ""), ("fishey", " (did you mean fisheye?)"),
                                       ("perspectiv", " (did you mean perspective?)"), ("my.lens", "")])
def test_a_word_that_is_neither_says_so(pano, capsys, where, word, hint):
    main, argv = commands(word)[where]
    prog = "tracer render" if main is tracer else "lenslab warp"
    assert run(capsys, main, argv) == (2, f"{prog}: error: no lens model and no file named {word!r}{hint}; "
                                          f"valid models: {MODELS}\n")
    assert sorted(p.name for p in pano.parent.iterdir()) == ["pano.exr"]


def test_the_list_is_every_registered_model():
    from lenslab.lenses import REGISTRY

    assert MODELS.split(", ") == sorted(REGISTRY)


@pytest.mark.parametrize("where", list(commands("x")))
def test_a_spec_with_parameters_is_an_unknown_model(pano, capsys, where):
    main, argv = commands("fishey:fov=180")[where]
    prog = "tracer render" if main is tracer else "lenslab warp"
    assert run(capsys, main, argv) == (2, f"{prog}: error: unknown lens model 'fishey' (did you mean fisheye?); "
                                          f"valid models: {MODELS}\n")


@pytest.mark.parametrize("where", list(commands("x")))
@pytest.mark.parametrize("name", ["missing.exr", "dir/missing", "missing.yaml"])
def test_a_name_only_a_file_has_is_a_missing_file(pano, capsys, where, name):
    main, argv = commands(name)[where]
    prog = "tracer render" if main is tracer else "lenslab warp"
    assert run(capsys, main, argv) == (1, f"{prog}: error: {name}: {os.strerror(errno.ENOENT).lower()}\n")
