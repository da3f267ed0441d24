"""An empty value for a name, spec or file option (``--curve ''``, ``--from ''``, ``--camera ''``,
``--env ''``, ``--scene ''``, ``--lensfun ''``) is a usage error (exit 2, one line naming the option), never a
silent fall-back to the option's default: a script whose variable came out empty must not get hable, the
file's own camera, a constant sky or the whole lensfun database."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main as lenslab
from tracer.cli import main as tracer

RENDER = ["render", "--size", "8x8", "--spp", "1", "-q"]


@pytest.fixture
def pano(tmp_path):
    return lio.write(tmp_path / "pano.exr", np.full((8, 16, 3), 0.5, np.float32))


@pytest.mark.parametrize("main, argv, option", [
    (lenslab, ["tonemap", "{pano}", "-o", "{d}/out.png", "--curve", ""], "--tone/--curve"),  # argparse names both
    (lenslab, ["warp", "{pano}", "--to", "fisheye", "--from", " ", "-o", "{d}/out.exr"], "--from"),
    (tracer, [*RENDER, "--camera", "", "-o", "{d}/out.exr"], "--camera"),
    (tracer, [*RENDER, "--scene", "sky", "--env", "", "-o", "{d}/out.exr"], "--env"),
    (tracer, [*RENDER, "--scene", "", "-o", "{d}/out.exr"], "--scene"),
    (lenslab, ["lenses", "--lensfun", ""], "--lensfun"),  # would list the whole lensfun database
])
def test_empty_value_is_a_usage_error(tmp_path, pano, capsys, main, argv, option):
    argv = [a.format(pano=pano, d=tmp_path) for a in argv]
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"error: argument {option}: is empty" in err[0], err
    assert not (tmp_path / "out.exr").exists() and not (tmp_path / "out.png").exists()
