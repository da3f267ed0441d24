"""``lenslab curves``: an empty ``--curves`` is a usage error (exit 2, one line), not every curve; ``--stops``
(shifted by ``--exposure``) must stay within the stops a 32-bit float holds, which NumPy's ``finfo`` gives: a
range beyond them would sample 0 or inf and chart the repairs rather than the curves."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

F32 = np.finfo(np.float32)
LOWEST, HIGHEST = int(F32.minexp), int(F32.maxexp) - 1  # -126 and 127: 2**128 is inf in float32


def test_float32_bounds_are_what_numpy_says():
    assert 2.0 ** HIGHEST <= float(F32.max) < 2.0 ** (HIGHEST + 1)
    assert float(F32.tiny) == 2.0 ** LOWEST  # the smallest normal float32


@pytest.mark.parametrize("curves", ["", " , "])
def test_empty_curves_is_a_usage_error(tmp_path, capsys, curves):
    out = tmp_path / "c.png"
    assert main(["curves", "--curves", curves, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--curves is empty" in err[0] and "hable" in err[0]
    assert not out.exists()


@pytest.mark.parametrize("argv", [["--stops", "-10", str(HIGHEST + 1)],
                                  ["--stops", str(LOWEST - 1), "0"],
                                  ["--stops", "-10", str(HIGHEST - 4), "--exposure", "5"]])
def test_stops_beyond_float32_are_a_usage_error(tmp_path, capsys, argv):
    out = tmp_path / "c.png"
    assert main(["curves", *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"within {LOWEST} and {HIGHEST} stops" in err[0], err
    assert not out.exists()


def test_the_whole_float32_range_charts_without_repairs(tmp_path, capsys):
    out = tmp_path / "c.svg"
    assert main(["curves", "--curves", "reinhard-extended,hable", "--stops", str(LOWEST), str(HIGHEST),
                 "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "repaired" not in err and out.stat().st_size > 0
