"""``--display`` gives a display's code values; EXR, Radiance HDR and PFM hold scene-linear light, so asking
for both is a usage error known from the arguments: one line, exit status 2, before any input is read (the
input here holds bytes that are no image: a read would have failed it, exit status 1), and no note before it
(a note about the file's tags would describe a file that is never written)."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main

LINE = ("Display P3: a display transform gives display code values and {title} holds scene-linear light: "
        "write jpg, png, ppm or tiff, or leave --display out")


@pytest.mark.parametrize("command, ext, title", [
    (["convert", "--to", "exr"], "exr", "OpenEXR"),
    (["convert", "--to", "hdr"], "hdr", "Radiance HDR"),
    (["convert", "--to", "pfm"], "pfm", "PFM"),
    (["warp", "--to", "equirect"], "exr", "OpenEXR"),
    (["warp", "--to", "equirect"], "hdr", "Radiance HDR"),
    (["tonemap"], "exr", "OpenEXR"),
    (["tonemap"], "hdr", "Radiance HDR"),
])
def test_a_display_to_a_scene_linear_format_is_a_usage_error(tmp_path, capsys, command, ext, title):
    src = tmp_path / "sunset.exr"
    src.write_bytes(b"not an image\n" * 8)
    out = tmp_path / f"y.{ext}"
    code = main([command[0], str(src), *command[1:], "-o", str(out), "--display", "Display P3"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2, lines
    assert lines == [f"lenslab {command[0]}: error: " + LINE.format(title=title)]
    assert not out.exists()


def test_a_display_to_tiff_is_written(tmp_path, capsys):
    """TIFF holds the codes as integers: the same display is no error there (the rule is the format's)."""
    import numpy as np

    from lenslab.io import read, write

    write(tmp_path / "sunset.exr", np.full((4, 8, 3), 0.18, np.float32))
    assert main(["convert", str(tmp_path / "sunset.exr"), "--to", "tiff", "-o", str(tmp_path / "y.tif"),
                 "--display", "Display P3", "-q"]) == 0
    assert read(tmp_path / "y.tif")[0].shape[:2] == (4, 8)
