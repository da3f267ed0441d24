"""``lenslab validate``: empty ``--filters``, ``--pano-sizes``, ``--direct-spp`` or ``--scene``, and a scene name
that is neither built in nor a scene file, are known from the command line alone: a usage error (exit 2, one
line) before anything is traced, and no report folder is made."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main

BASE = ["validate", "--scene", "analytic", "--noise-free", "--size", "16x16", "--pano-sizes", "64x32",
        "--filters", "bilinear", "-q"]


@pytest.mark.parametrize("extra, words", [
    (["--filters", ""], "--filters is empty"),
    (["--filters", " , "], "--filters is empty"),
    (["--pano-sizes", ""], "--pano-sizes is empty"),
    (["--direct-spp", ""], "argument --direct-spp: is empty"),
    (["--scene", ""], "argument --scene: is empty"),
    (["--scene", "cornel"], "'cornel' is neither a built-in scene"),
])
def test_names_known_to_be_wrong_are_usage_errors(tmp_path, capsys, extra, words):
    out = tmp_path / "report"
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main([*BASE, *extra, "-o", str(out)]))
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not out.exists()
