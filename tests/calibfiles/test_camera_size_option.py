"""``lenslab camera show/convert --size``: a size that is not WIDTHxHEIGHT with both sides at least 1 is a
mistake in what was typed: exit status 2 and one line naming the option, as ``warp`` and ``fit`` say it,
before the camera is read; a good size scales the intrinsics (fx with the width, as OpenCV's do)."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main

SPEC = "opencv:fx=900,fy=900,cx=639.5,cy=359.5,k1=-0.2,width=1280,height=720"


@pytest.mark.parametrize("action", ["show", "convert"])
@pytest.mark.parametrize("size", ["10", "0x10", "axb", "640x"])
def test_bad_size_is_a_usage_error(tmp_path, capsys, action, size):
    out = tmp_path / "cam.yaml"
    argv = ["camera", action, "no-such-camera.yaml", "--size", size] + (["-o", str(out)] if action == "convert" else [])
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "--size" in lines[0] and "no-such-camera" not in lines[0], lines
    assert not out.exists()


def test_good_size_scales_the_camera(capsys):
    assert main(["camera", "show", SPEC, "--size", "640x360"]) == 0
    out = capsys.readouterr().out
    assert ", 640x360" in out.splitlines()[0]
    assert "fx       450" in out  # 900 px at 1280 wide is 450 px at 640
