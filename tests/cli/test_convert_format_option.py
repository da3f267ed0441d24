"""``lenslab convert`` takes its output format as ``--format`` too, the name ``warp`` and ``tonemap`` give
it, besides its own ``--to``: the same file either way (read back with OpenCV)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


def test_the_format_option_has_both_names(tmp_path):
    src = tmp_path / "in.exr"
    write(src, np.random.default_rng(2).random((4, 6, 3)).astype(np.float32))
    got = {}
    for option in ("--to", "--format"):
        out = tmp_path / option.strip("-")
        assert main(["convert", str(src), option, "png", "-o", str(out)]) == 0
        got[option] = cv2.imread(str(out / "in.png"), cv2.IMREAD_UNCHANGED)
    assert got["--to"].shape == (4, 6, 3) and np.array_equal(got["--to"], got["--format"])


def test_help_names_both():
    import io
    from contextlib import redirect_stdout

    buf = io.StringIO()
    with redirect_stdout(buf), pytest.raises(SystemExit):
        main(["convert", "--help"])
    assert "--to FORMAT, --format FORMAT" in buf.getvalue()
