"""``lenslab validate --look-at X,Y,Z`` with ``--yaw``, ``--pitch`` or ``--roll`` (0 too): a usage error naming both,
as ``lenslab warp`` gives, before anything is rendered; one of the two used to be dropped without a word (the turn
won, so ``--pitch 0`` threw the --look-at away)."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main as lenslab


@pytest.mark.parametrize("turn", [["--pitch", "0"], ["--yaw", "10"], ["--roll", "0", "--pitch", "5"]])
def test_look_at_with_a_turn_is_a_usage_error(tmp_path, monkeypatch, capsys, turn):
    import lenslab.validate.run as run

    def validate(*args, **kwargs):  # (what would run: never reached)
        raise AssertionError("validated with one of --look-at and the turns dropped")

    monkeypatch.setattr(run, "validate", validate)
    out = tmp_path / "v"
    assert lenslab(["validate", "--scene", "cornell", "--look-at", "0,0,1", *turn, "--size", "16x16",
                    "-o", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == ["lenslab validate: error: give either --look-at or --yaw/--pitch/--roll, not both"]
    assert not out.exists()
