"""``width=`` or ``height=`` in the spec of a model that takes no such parameter (the image's size is given apart,
``--size``) is an unknown parameter like any other: one line listing the valid ones, exit 2 (a usage mistake), never
Python's ``TypeError`` of a keyword given twice (exit 1). A calibrated model whose spec holds its calibration size
(``opencv:...,width=640,height=480``) takes them as before."""

from __future__ import annotations

import pytest

from lenslab import make_lens
from lenslab.errors import LensError
from lenslab.lenses.registry import REGISTRY


def _sizeless():
    return [m for m in REGISTRY if not hasattr(REGISTRY[m], "from_values")
            and not {"width", "height"} & {p.name for p in REGISTRY[m].params}]


def test_every_model_without_a_size_parameter_refuses_one_by_name():
    models = _sizeless()
    assert {"perspective", "fisheye", "equirect"} <= set(models)
    for model in models:
        with pytest.raises(LensError, match=rf"^{model}: unknown parameter\(s\) width; valid: "):
            make_lens(f"{model}:width=640", (64, 32))


@pytest.mark.parametrize("command", [["warp", "in.exr", "-o", "o.exr", "--to"], ["stmap", "--from", "equirect",
                                                                               "--size", "8x8", "-o", "m.exr", "--to"]])
def test_the_commands_say_it_in_one_line_with_exit_2(tmp_path, capsys, monkeypatch, command):
    from lenslab.cli.main import main

    monkeypatch.chdir(tmp_path)
    assert main([*command, "perspective:fov=90,width=640,height=480"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown parameter(s) height, width; valid: fov, vfov, dfov" in err, err
    assert "TypeError" not in err


def test_a_calibrated_spec_keeps_its_size():
    lens = make_lens("opencv:fx=500,fy=500,cx=319.5,cy=239.5,width=640,height=480", (640, 480))
    assert (lens.width, lens.height) == (640, 480)
