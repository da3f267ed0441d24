"""``lenslab info`` of an Ultra HDR JPEG says on its first line that the 8-bit file was read as linear HDR light (its
gain map applied), where a plain JPEG says 'sRGB-decoded to linear': the values below it go past 1. The file is
written here from the specification (tests.gainmap.files); its ``:sdr`` read keeps the plain JPEG's words."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from tests.gainmap.files import jpeg, ultrahdr


def test_the_first_line_says_hdr(tmp_path, capsys):
    path = tmp_path / "photo.jpg"
    path.write_bytes(ultrahdr(jpeg(np.full((16, 32, 3), 200)), jpeg(np.full((4, 8), 255)),
                              {"GainMapMin": 0, "GainMapMax": 2, "HDRCapacityMin": 0, "HDRCapacityMax": 2}))
    capsys.readouterr()
    assert main(["info", str(path)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.endswith("uint 8-bit, read as its HDR rendition: linear light"), first
    assert main(["info", f"{path}:sdr"]) == 0
    assert capsys.readouterr().out.splitlines()[0].endswith("uint 8-bit, sRGB-decoded to linear")
