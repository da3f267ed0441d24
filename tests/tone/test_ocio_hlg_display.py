"""HLG display transforms need a config with an HLG display: OpenColorIO's built-in default config has none, and
``--display Rec.2100-HLG`` is refused there in one line (exit 2) that lists the displays the config has; its
built-in studio config has one, and the PNG made through it says HLG in its cICP chunk. Expected values:
PyOpenColorIO's own list of each config's displays; ITU-T H.273's code points (primaries 9, BT.2020; transfer
18, ARIB STD-B67 HLG)."""

from __future__ import annotations

import struct
import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio

OCIO = pytest.importorskip("PyOpenColorIO")


def _tonemap(tmp_path, *args):
    src = tmp_path / "s.exr"
    lio.write(src, np.full((8, 12, 3), 0.5, np.float32))
    return subprocess.run([sys.executable, "-m", "lenslab", "tonemap", str(src), "-o", str(tmp_path / "o.png"),
                           "--display", "Rec.2100-HLG", *args], capture_output=True, text=True)


def _displays(name):
    return list(OCIO.Config.CreateFromFile(name).getDisplays())


def test_the_default_config_has_no_hlg_display_and_the_refusal_lists_its_displays(tmp_path):
    displays = _displays("ocio://default")
    assert not any("HLG" in d for d in displays)
    run = _tonemap(tmp_path)
    assert run.returncode == 2 and not (tmp_path / "o.png").exists()
    [line] = run.stderr.strip().splitlines()
    assert line.startswith("lenslab tonemap: error: display 'Rec.2100-HLG' is not one of the config's: ")
    assert line.split("config's: ", 1)[1].split("; ") == displays


def test_the_studio_config_writes_an_hlg_png(tmp_path):
    displays = _displays("ocio://studio-config-latest")
    assert "Rec.2100-HLG - Display" in displays
    run = _tonemap(tmp_path, "--ocio", "ocio://studio-config-latest")
    assert run.returncode == 0, run.stderr
    data = (tmp_path / "o.png").read_bytes()
    at = data.index(b"cICP")
    assert struct.unpack(">I", data[at - 4:at]) == (4,)
    assert tuple(data[at + 4:at + 8]) == (9, 18, 0, 1)  # BT.2020 primaries, HLG, RGB, full range
