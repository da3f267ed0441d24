"""A pose option given on the command line is given, whatever its value: ``--yaw 0`` with ``--to render.exr`` (an
image that records its camera) is refused as ``--yaw 10`` is (exit 2, naming the spec to turn instead); it used to
pass unseen because 0 was the option's default. Left out, the options mean what they meant: no turn, or the
recorded view's orientation.

Expected orientations are the rotation ``Ry(yaw) Rx(-pitch) Rz(roll)`` of docs/conventions.md, transcribed in float64
by the tests of ``--to render.exr`` (test_warp_to_render_pose); expected messages are the exact lines the commands
print.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import read, write
from tests.commands.test_warp_to_render_pose import PITCH, ROLL, SIZE, YAW, _rotation
from tracer.cli import main as tracer


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pose")
    render = folder / "render.exr"
    assert tracer(["render", "--camera", "perspective:fov=60", "--size", f"{SIZE[0]}x{SIZE[1]}", "--spp", "1",
                   "--yaw", str(YAW), "--pitch", str(PITCH), "--roll", str(ROLL), "-o", str(render), "-q"]) == 0
    pano = folder / "pano.exr"
    write(pano, np.ones((32, 64, 3), np.float32))  # no camera recorded: a photographed panorama
    return folder, render, pano


def _refusal(command: str, flag: str, option: str, render, spec_option: str | None = None) -> str:
    return (f"{command}: error: {flag}: {option} {render} takes the view that file records, its lens and its "
            f"orientation (yaw 30, pitch -15, roll 5); to turn that lens another way, give it as a spec: "
            f"{spec_option or option} perspective:fov=60")


@pytest.mark.parametrize("flag", ["--yaw", "--pitch", "--roll"])
@pytest.mark.parametrize("value", ["0", "-0", "0.0"])
def test_a_zero_turn_with_a_recorded_view_is_refused(files, capsys, flag, value):
    folder, render, pano = files
    out = folder / "view.exr"
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "--to", str(render), "-o", str(out), flag, value]) == 2
    assert capsys.readouterr().err == _refusal("lenslab warp", flag, "--to", render) + "\n"
    assert lenslab(["stmap", "--from", "equirect", "--to", str(render), "--size", "32x24", "-o",
                    str(folder / "map.exr"), flag, value]) == 2
    assert capsys.readouterr().err == _refusal("lenslab stmap", flag, "--to", render) + "\n"
    assert tracer(["render", "--scene", "furnace", "--camera", str(render), "--spp", "1", "-q", "-o",
                   str(folder / "again.exr"), flag, value]) == 2
    assert capsys.readouterr().err == _refusal("tracer render", flag, "--camera", render) + "\n"
    assert not out.exists() and not (folder / "map.exr").exists() and not (folder / "again.exr").exists()


@pytest.mark.parametrize("flag", ["--yaw", "--pitch", "--roll"])
def test_validate_refuses_a_turn_of_a_reference_that_records_its_camera(files, capsys, flag):
    """``lenslab validate --reference render.exr``: the reference's camera is the one its file records, orientation
    and all; a turn given with it was ignored, whatever its value."""
    folder, render, pano = files
    capsys.readouterr()
    assert lenslab(["validate", "--reference", str(render), "--source", str(pano), "-o", str(folder / "report"),
                    flag, "0"]) == 2
    assert capsys.readouterr().err == _refusal("lenslab validate", flag, "--reference", render,
                                               "--reference-camera") + "\n"
    assert not (folder / "report").exists()


def test_zero_turns_and_look_at_are_one_too_many(files, capsys):
    folder, _, pano = files
    capsys.readouterr()
    assert lenslab(["warp", str(pano), "--to", "fisheye", "--look-at", "0,0,1", "--pitch", "0", "-o",
                    str(folder / "x.exr")]) == 2
    assert capsys.readouterr().err == "lenslab warp: error: give either --look-at or --yaw/--pitch/--roll, not both\n"


def test_without_pose_options_the_view_is_the_render_s(files):
    folder, render, pano = files
    out = folder / "same.exr"
    assert lenslab(["warp", str(pano), "--to", str(render), "-o", str(out), "-q", "--overwrite"]) == 0
    np.testing.assert_allclose(read(out)[1]["camera"].pose.rotation, _rotation(YAW, PITCH, ROLL), atol=1e-12)


@pytest.mark.parametrize("options,ypr", [([], (0, 0, 0)), (["--yaw", "0"], (0, 0, 0)), (["--pitch", "20"], (0, 20, 0)),
                                         (["--yaw", "-40", "--roll", "0"], (-40, 0, 0))])
def test_a_lens_spec_is_turned_as_before(files, options, ypr):
    """Left out, a turn is 0; given, its value: the output's recorded orientation (``--to`` a lens spec)."""
    folder, _, pano = files
    out = folder / "turned.exr"
    assert lenslab(["warp", str(pano), "--to", "perspective:fov=60", "--size", "16x16", "-o", str(out), "-q",
                    "--overwrite", *options]) == 0
    np.testing.assert_allclose(read(out)[1]["camera"].pose.rotation, _rotation(*ypr), atol=1e-12)


def test_validate_sees_a_pitch_given_alone(tmp_path, monkeypatch):
    """``lenslab validate --pitch 10`` turns the target up 10 degrees from +z (as ``--yaw`` does); it used to keep the
    scene view's direction when --yaw was left out."""
    import lenslab.validate.run as run

    seen = {}

    class Stop(Exception):
        pass

    def validate(source, target, *args, **kwargs):
        seen["target"] = target
        raise Stop

    monkeypatch.setattr(run, "validate", validate)
    # (the funnel reports the stop as a failure: the target is what is looked at)
    argv = ["validate", "--scene", "cornell", "--pitch", "10", "--size", "16x16", "-o", str(tmp_path / "v")]
    assert lenslab(argv) == 1
    np.testing.assert_allclose(seen["target"].pose.rotation, _rotation(0, 10, 0), atol=1e-12)
