"""An output name that is a device (``-o /dev/null``) is refused for what it is, not taken for a folder."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["tonemap"]])
def test_a_device_without_an_extension_is_named_as_not_a_regular_file(tmp_path, command, capsys):
    pano = tmp_path / "pano.exr"
    write(pano, np.full((8, 16, 3), 0.5, np.float32))
    # -o /dev/null has no extension, so it is not taken for a file name; the cause is still the device
    status = main([command[0], str(pano), "-o", "/dev/null", *command[1:], "--overwrite"])
    err = capsys.readouterr().err
    assert status == 1, err
    assert err.count("\n") == 1 and "/dev/null" in err and "not a regular file" in err and "folder" not in err, err
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
