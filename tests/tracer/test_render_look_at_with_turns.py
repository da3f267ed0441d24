"""``tracer render --look-at X,Y,Z`` with ``--yaw``, ``--pitch`` or ``--roll`` (0 too): a usage error, as ``lenslab
warp`` and ``lenslab validate`` give, before anything is traced; the turn used to be dropped without a word."""

from __future__ import annotations

import pytest

from tracer.cli import main as tracer


@pytest.mark.parametrize("turn", [["--yaw", "10"], ["--pitch", "0"], ["--roll", "-5"]])
def test_look_at_with_a_turn_is_a_usage_error(tmp_path, capsys, turn):
    out = tmp_path / "t.exr"
    assert tracer(["render", "--scene", "cornell", "--camera", "fisheye", "--look-at", "0,0,1", *turn,
                   "--size", "16x16", "--spp", "1", "-o", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == ["tracer render: error: give either --look-at or --yaw/--pitch/--roll, not both"]
    assert not out.exists()
