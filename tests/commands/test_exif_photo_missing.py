"""``exif:photo=PHOTO`` naming a photo that is not there is a missing input, in every command alike: exit 1 and the
operating system's own words (``os.strerror``), as a missing image, camera file or ST map is; not a usage error of
the spec (exit 2) in one command and a missing file in another."""

from __future__ import annotations

import errno
import os

import pytest

from lenslab.cli.main import main


@pytest.mark.parametrize("argv", [
    ["warp", "{d}/pano.exr", "-o", "{d}/o.exr", "--size", "8x8", "--to", "exif:photo={photo}"],
    ["stmap", "--from", "exif:photo={photo}", "--to", "equirect", "--size", "8x4", "-o", "{d}/m.exr"],
], ids=["warp", "stmap"])
@pytest.mark.parametrize("what, code", [("missing.jpg", errno.ENOENT), ("", errno.EISDIR)], ids=["missing", "folder"])
def test_a_photo_that_is_not_there_is_a_missing_input(tmp_path, capsys, argv, what, code):
    import numpy as np

    import lenslab.io as lio

    lio.write(tmp_path / "pano.exr", np.ones((8, 16, 3), np.float32))
    photo = tmp_path / what if what else tmp_path
    assert main([a.format(d=tmp_path, photo=photo) for a in argv]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{photo}: {os.strerror(code).lower()}" in err.lower(), err
