"""An output folder that cannot be made (``-o /sys/out/``: sysfs takes no new folder, for root either) is refused in
one line that says the folder cannot be made and why (the system's reason), exit 1, not a bare 'operation not
permitted'."""

from __future__ import annotations

import os

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.mark.skipif(not os.path.isdir("/sys/kernel"), reason="needs Linux's sysfs, which takes no new folder")
def test_a_folder_that_cannot_be_made(tmp_path, capsys):
    src = tmp_path / "pano.exr"
    write(src, np.full((8, 16, 3), 0.5, np.float32))
    capsys.readouterr()
    assert main(["convert", str(src), "-o", "/sys/lenslab-out/", "--to", "png"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("lenslab convert: error: /sys/lenslab-out: the folder cannot be made ("), err
    assert len(err.splitlines()) == 1
