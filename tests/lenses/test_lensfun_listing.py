"""``lenslab lenses --lensfun``: the vignetting line keeps focal lengths, f-numbers and distances apart,
each as lensfunpy's database holds them."""

from __future__ import annotations

import pytest

lf = pytest.importorskip("lensfunpy")

from lenslab.cli.main import main  # noqa: E402

LENS = "Samyang 8mm f/2.8 UMC Fish-eye"


def test_vignetting_line_separates_apertures_and_distances(capsys):
    lens = next(l for l in lf.Database().lenses if l.model == LENS)
    vig = lens.calib_vignetting
    apertures = ", ".join(f"f/{a:g}" for a in sorted({float(e.aperture) for e in vig}))
    distances = ", ".join(f"{d:g}" for d in sorted({float(e.distance) for e in vig}))
    assert main(["lenses", "--lensfun", "samyang 8mm f/2.8"]) == 0
    block = capsys.readouterr().out.split(LENS, 1)[1].split("\n\n", 1)[0]
    line = next(l for l in block.splitlines() if l.strip().startswith("vignetting"))
    assert line.split("vignetting", 1)[1].strip() == (
        f"pa, {len(vig)} entries; focal 8 mm; aperture {apertures}; distance {distances} m")
    assert len({float(e.aperture) for e in vig}) > 1 and len({float(e.distance) for e in vig}) > 1
