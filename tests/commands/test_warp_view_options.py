"""``lenslab warp IN --to render.exr`` makes the view the render records; the options that would make another view of
it (``--flip``, which mirrors the rays; ``--autoscale``, which scales the lens's field; ``--rotation-order``, the
order of turns that are refused with it) are a usage error naming the spec to give instead, as ``--yaw`` is. They
used to be taken in silence: ``--flip h`` wrote the view at yaw -30 mirrored under a header that records yaw 30.
``--source-flip`` (a source stored mirrored) means the same with a recorded view as with a spec, and is applied.

``--rotation-order`` with no --yaw/--pitch/--roll orders nothing: a usage error, as the options that cannot apply
are (``--stmap`` with ``--rotation-order``, ``--tone`` with an EXR), also when the order given is the default.

The recorded orientation in the expected messages is the one given to ``tracer render``; the mirrored source is
mirrored by NumPy's ``[:, ::-1]``, outside lenslab.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import read, write
from tracer.cli import main as tracer

YAW, PITCH, ROLL = 30, -15, 5


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("view")
    render = folder / "render.exr"
    assert tracer(["render", "--camera", "perspective:fov=60", "--size", "32x24", "--spp", "1", "--yaw", str(YAW),
                   "--pitch", str(PITCH), "--roll", str(ROLL), "-o", str(render), "-q"]) == 0
    h, w = 32, 64
    y, x = np.mgrid[0:h, 0:w]
    pano = folder / "pano.exr"  # no camera recorded: a photographed panorama, every pixel its own value
    write(pano, np.stack([(x + 0.5) / w, (y + 0.5) / h, 0.25 + 0 * x], -1).astype(np.float32), pixel_type="float")
    return folder, render, pano


def _refusal(flags: str, what: str, render) -> str:
    # (an option that is no turn makes another view of the render's own: the line names the turns that give it)
    turns = "" if "turn" in what else f" --yaw {YAW} --pitch {PITCH} --roll {ROLL}"
    return (f"lenslab warp: error: {flags}: --to {render} takes the view that file records, its lens and its "
            f"orientation (yaw {YAW}, pitch {PITCH}, roll {ROLL}); to {what}, give it as a spec: "
            f"--to perspective:fov=60{turns}\n")


@pytest.mark.parametrize("options,flags,what", [
    (["--flip", "h"], "--flip", "mirror that lens's rays"),
    (["--flip", "d"], "--flip", "mirror that lens's rays"),
    (["--autoscale"], "--autoscale", "scale that lens's field of view"),
    (["--autoscale", "cover"], "--autoscale", "scale that lens's field of view"),
    (["--rotation-order", "pyr"], "--rotation-order", "turn that lens another way"),
    (["--rotation-order", "ypr"], "--rotation-order", "turn that lens another way"),
    (["--yaw", "0", "--flip", "v"], "--yaw/--flip", "turn that lens another way or mirror that lens's rays"),
])
def test_options_that_make_another_view_are_refused(files, capsys, options, flags, what):
    folder, render, pano = files
    out = folder / "view.exr"
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "-o", str(out), "--to", str(render), *options]) == 2
    assert capsys.readouterr().err == _refusal(flags, what, render)
    assert not out.exists() and not list(folder.glob(".*view*"))


def test_a_mirrored_source_is_read_mirrored_for_a_recorded_view(files):
    """--source-flip h: the warp of a source stored mirrored is the warp of the source NumPy mirrors back."""
    folder, render, pano = files
    mirrored = folder / "mirrored.exr"
    write(mirrored, np.ascontiguousarray(read(pano)[0][:, ::-1]), pixel_type="float", overwrite=True)
    plain, flipped = folder / "plain.exr", folder / "flipped.exr"
    common = ["--to", str(render), "--pixel-type", "float", "-q", "--overwrite"]
    assert lenslab(["warp", str(pano), "-o", str(plain), *common]) == 0
    assert lenslab(["warp", str(mirrored), "-o", str(flipped), "--source-flip", "h", *common]) == 0
    a, b = read(plain)[0], read(flipped)[0]
    assert a.shape == (24, 32, 4)
    # the same source texels at the same weights, in float32: equal to its rounding
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-6)
    assert read(flipped)[1]["camera"].size == (32, 24)


@pytest.mark.parametrize("options", [[], ["--look-at", "1,0,0"], ["--eye", "0,0,0"]])
@pytest.mark.parametrize("order", ["pyr", "ypr"])
def test_a_rotation_order_with_no_turn_is_refused(files, capsys, options, order):
    folder, _, pano = files
    out = folder / "ordered.exr"
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "-o", str(out), "--to", "perspective:fov=60", "--size", "16x16",
                    "--rotation-order", order, *options]) == 2
    look = " (--look-at gives a direction, in no order)" if "--look-at" in options else ""
    assert capsys.readouterr().err == (
        f"lenslab warp: error: --rotation-order {order} orders the turns of --yaw, --pitch and --roll, and none is "
        f"given{look}: it would change nothing; drop it, or give the turns it orders\n")
    assert not out.exists()


def test_a_rotation_order_with_turns_orders_them(files):
    """--rotation-order rpy with --yaw 30 --pitch 20: roll is applied last (first in the product): the output's
    recorded rotation is Rz(roll) Rx(-pitch) Ry(yaw), transcribed here in float64 (docs/conventions.md's turns)."""
    folder, _, pano = files
    out = folder / "turned.exr"
    assert lenslab(["warp", str(pano), "-o", str(out), "--to", "perspective:fov=60", "--size", "16x16", "-q",
                    "--overwrite", "--rotation-order", "rpy", "--yaw", "30", "--pitch", "20"]) == 0
    y, p = np.radians([30.0, 20.0])
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    rx = np.array([[1, 0, 0], [0, np.cos(-p), -np.sin(-p)], [0, np.sin(-p), np.cos(-p)]])
    np.testing.assert_allclose(read(out)[1]["camera"].pose.rotation, rx @ ry, atol=1e-12)


def test_the_stmap_refuses_a_rotation_order_given_as_the_default(files, capsys):
    folder, _, pano = files
    stmap = folder / "map.exr"
    assert lenslab(["stmap", "--from", "equirect", "--to", "perspective:fov=60", "--size", "8x8", "--source-size",
                    "64x32", "-o", str(stmap), "-q"]) == 0
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "-o", str(folder / "st.exr"), "--stmap", str(stmap),
                    "--rotation-order", "ypr"]) == 2
    assert capsys.readouterr().err == "lenslab warp: error: --stmap gives the whole geometry; drop --rotation-order\n"
