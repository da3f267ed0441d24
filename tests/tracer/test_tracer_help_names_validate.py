"""``tracer --help`` tells where the check of a warp against a render lives (``lenslab validate``), for a user who
looks for it beside ``tracer render``; and that command exists."""

from __future__ import annotations

import pytest


def test_tracer_help_names_lenslab_validate(capsys):
    from tracer.cli import main

    with pytest.raises(SystemExit) as done:
        main(["--help"])
    assert done.value.code == 0
    assert "lenslab validate" in capsys.readouterr().out


def test_lenslab_validate_is_a_command(capsys):
    from lenslab.cli.main import main

    with pytest.raises(SystemExit) as done:
        main(["validate", "--help"])
    assert done.value.code == 0
    assert "Check warps against direct ray-traced renders" in capsys.readouterr().out
