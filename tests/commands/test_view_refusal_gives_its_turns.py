"""``--flip`` or ``--autoscale`` with ``--to view.exr`` (an image that records its camera) is refused, naming the spec
to give instead; the options it names give that file's view, its turns (and a flop's own --flip) with the spec: the
spec alone (``--to perspective:fov=60``) was a view at yaw 0 where the file records yaw 30, pitch -15, roll 5, and a
user who added --flip to it mirrored another view without a word.

Outside values: the turns are those given to ``tracer render`` (or to the warp that made the flop), and the check is
that the options named, run as the line says, give the file's view: the same pixels as ``--to view.exr``."""

from __future__ import annotations

import shlex

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import read, write
from tracer.cli import main as tracer


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("refusal")
    render = folder / "render.exr"
    assert tracer(["render", "--camera", "perspective:fov=60", "--size", "32x24", "--spp", "1", "--yaw", "30",
                   "--pitch", "-15", "--roll", "5", "-o", str(render), "-q"]) == 0
    y, x = np.mgrid[0:32, 0:64]
    pano = folder / "pano.exr"
    write(pano, np.stack([(x + 0.5) / 64, (y + 0.5) / 32, 0.25 + 0 * x], -1).astype(np.float32), pixel_type="float")
    flop = folder / "flop.exr"
    assert lenslab(["warp", str(pano), "-o", str(flop), "--to", "perspective:fov=70", "--size", "24x16", "--yaw", "30",
                    "--pitch", "20", "--roll", "10", "--flip", "v", "-q"]) == 0
    return folder, pano, {"render": render, "flop": flop}


@pytest.mark.parametrize("which", ["render", "flop"])
@pytest.mark.parametrize("option", [["--flip", "h"], ["--autoscale"]])
def test_the_spec_named_gives_the_files_view(files, capsys, which, option):
    folder, pano, views = files
    view = views[which]
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "-o", str(folder / "x.exr"), "--to", str(view), *option]) == 2
    line = capsys.readouterr().err.strip()
    named = shlex.split(line.rsplit("give it as a spec: ", 1)[1])
    assert named[0] == "--to"
    size = "x".join(str(n) for n in read(view)[1]["size"])
    want, got = folder / f"want-{which}.exr", folder / f"got-{which}.exr"
    for out, to in ((want, ["--to", str(view)]), (got, named + ["--size", size])):
        assert lenslab(["warp", str(pano), "-o", str(out), *to, "--pixel-type", "float", "--overwrite", "-q"]) == 0
    a, b = read(want)[0], read(got)[0]
    assert np.array_equal(a, b), (named, np.abs(a - b).max())
