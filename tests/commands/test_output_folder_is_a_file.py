"""An output whose folder is a file (``-o photo.exr/x.png``, a typo for ``-o photo.png``) is refused, exit 1 before
anything is read, by saying that the folder is a file (the test makes it one), not that the folder does not exist."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.mark.parametrize("tail", ["x.png", "sub/x.png"])
def test_a_file_named_as_the_output_folder(tmp_path, capsys, tail):
    src = tmp_path / "pano.exr"
    write(src, np.full((8, 16, 3), 0.5, np.float32))
    out = f"{src}/{tail}"
    capsys.readouterr()
    assert main(["convert", str(src), "-o", out]) == 1
    err = capsys.readouterr().err.strip()
    assert err == f"lenslab convert: error: {out}: {src} is a file, not a folder", err
