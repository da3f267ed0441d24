"""A selector that names nothing in an EXR (``Adjuster.exr:bogus``) is one error line listing what the
file offers, views included (a view is a valid selector: ``Adjuster.exr:center``), and no part list of
empty names (``parts: ''``) for a single unnamed part. Expected values: the views of the file's
``multiView`` attribute and its layers, as OpenImageIO reads them."""

from __future__ import annotations

import subprocess
import sys
import numpy as np
import pytest

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")

def _multiview(path):
    """A one-part multi-view file with no part name: default view ``center`` (R, G, B), ``left.*``, ``right.*``."""
    h, w = 6, 8
    chans = {}
    for prefix in ("", "left.", "right."):
        for c in "RGB":
            chans[prefix + c] = np.full((h, w), 0.5, np.float16)
    header = {"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION,
              "multiView": ["center", "left", "right"]}
    OpenEXR.File(header, chans).write(str(path))
    return path


def _oiio_views_and_layers(path):
    spec = oiio.ImageInput.open(str(path)).spec()
    views = list(spec.getattribute("multiView") or [])
    layers = sorted({n.rsplit(".", 1)[0] for n in spec.channelnames if "." in n})
    return views, layers


@pytest.mark.parametrize("which", ["made", "shared"])
def test_a_bad_selector_lists_views_and_layers_in_one_line(tmp_path, request, which):
    if which == "shared":  # the real Adjuster.exr (skips only where ../shared/data is absent)
        src = request.getfixturevalue("shared_data") / "formats" / "openexr-images" / "MultiView" / "Adjuster.exr"
    else:
        src = _multiview(tmp_path / "mv.exr")
    views, layers = _oiio_views_and_layers(src)
    assert views == ["center", "left", "right"] and layers == ["left", "right"]
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", f"{src}:bogus", "--to", "exr",
                          "-o", str(tmp_path / "o.exr")], capture_output=True, text=True)
    assert run.returncode == 1
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1, run.stderr
    assert "no part, layer or view named 'bogus'" in lines[0]
    assert f"layers: {', '.join(layers)}" in lines[0]
    assert f"views: {', '.join(views)}" in lines[0]
    assert "''" not in lines[0]  # the single part has no name: not listed as ''
    assert not (tmp_path / "o.exr").exists()
