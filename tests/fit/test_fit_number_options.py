"""``lenslab fit``'s numbers of pixels (``--tolerance``, ``--scale``, ``--outlier``, ``--max-pixels``) must be
above 0: anything else is a usage error (exit status 2, one line naming the option) before any file is read
or any fit runs, never a fit that cannot succeed (exit 1) or a Python error."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main


@pytest.mark.parametrize("argv, option", [
    (["fit", "lens", "--from", "fisheye:fov=180", "--model", "fisheye", "--size", "32x32", "--tolerance", "-1"],
     "--tolerance"),
    (["fit", "lens", "--from", "fisheye:fov=180", "--model", "fisheye", "--size", "32x32", "--tolerance", "nan"],
     "--tolerance"),
    (["fit", "points", "no-such.csv", "--model", "fisheye", "--size", "32x32", "--scale", "0"], "--scale"),
    (["fit", "points", "no-such.csv", "--model", "fisheye", "--size", "32x32", "--outlier", "-1"], "--outlier"),
    (["fit", "tone", "no-such.exr", "no-such.png", "--max-pixels", "0"], "--max-pixels"),
])
def test_non_positive_number_is_a_usage_error(capsys, argv, option):
    with pytest.raises(SystemExit) as exc:  # argparse's own exit
        main(argv)
    assert exc.value.code == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert out == "" and len(lines) == 1 and option in lines[0], lines
    assert "no-such" not in lines[0]  # said before any file is opened
