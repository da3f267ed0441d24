"""A lensfun lens without --size takes its calibration sensor's frame, landscape, long side over short the profile's
aspect ratio: ``tracer render --camera lensfun:...`` and ``lenslab warp --to lensfun:...`` rendered square before.

The aspect ratio is read here from lensfun's own database files (those lensfunpy bundles and loads), with
ElementTree: the lens's ``<aspect-ratio>`` (``4:3`` for the Canon PowerShot G12), else the 1.5 lensfun takes where
the XML gives none (the Canon EF 70-300mm DO). lensfunpy 1.18 exposes no
aspect ratio of its own; it finds each lens by the same model name.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

lensfunpy = pytest.importorskip("lensfunpy")

from lenslab.cli.main import main as lenslab  # noqa: E402
from lenslab.io import read, write  # noqa: E402

LENSES = {  # model -> the spec's focal length
    "Canon PowerShot G12 & compatibles (Standard)": 10,
    "Canon EF 70-300mm f/4.5-5.6 DO IS USM": 120,
}


def xml_aspect(model: str) -> float:
    """The lens's aspect ratio as lensfun's XML records it, or lensfun's default 1.5."""
    found = []
    for path in sorted((Path(lensfunpy.__file__).parent / "db_files").glob("*.xml")):
        for lens in ET.parse(path).getroot().iter("lens"):
            if any(m.text == model and not m.get("lang") for m in lens.findall("model")):
                found.append(lens.findtext("aspect-ratio"))
    assert len(found) == 1, found
    text = found[0]
    if text is None:
        return 1.5
    a, _, b = text.partition(":")
    return float(a) / float(b) if b else float(a)


def spec(model: str) -> str:
    return f"lensfun:lens={model},focal={LENSES[model]}"


def test_the_two_lenses_have_two_aspects():
    db = lensfunpy.Database()
    for model in LENSES:
        assert [lens.model for lens in db.lenses if lens.model == model] == [model]
    assert [xml_aspect(m) for m in LENSES] == [pytest.approx(4 / 3, abs=1e-12), 1.5]


@pytest.mark.parametrize("model", LENSES)
def test_tracer_renders_a_lensfun_lens_at_its_sensors_aspect(tmp_path, model):
    from tracer.cli import main as tracer

    out = tmp_path / "lens.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", spec(model), "--spp", "1", "-o", str(out), "-q"]) == 0
    h, w = read(out)[0].shape[:2]
    assert (w, h) == (round(512 * xml_aspect(model)), 512)  # the lens's own frame at 512 rows (tracer's help)


@pytest.mark.parametrize("model", LENSES)
def test_warp_to_a_lensfun_lens_without_size_takes_its_sensors_aspect(tmp_path, model):
    import numpy as np

    pano = tmp_path / "pano.exr"
    write(pano, np.full((64, 128, 3), 0.5, np.float32))
    out = tmp_path / "lens.exr"
    assert lenslab(["warp", str(pano), "-o", str(out), "--to", spec(model), "-q"]) == 0
    h, w = read(out)[0].shape[:2]
    assert w > h and w == round(h * xml_aspect(model))  # whole pixels: the width rounded from the rows
