"""A lens name that is neither a model nor a file, and close to no model's name, is still offered the spec it most
likely means: the name of a fisheye mapping (``stereographic``) the fisheye with that mapping, a longer spelling of
a model (``equirectangular``) the model. The spec offered is the one meant: its pixels map to the rays of the
projection named, by formulas transcribed here in float64 (Kannala and Brandt 2006, table 1; CONVENTIONS.md's
equirect)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from lenslab import make_lens
from lenslab.cli.main import main


def _offered(capsys, argv) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    found = re.search(r"\(did you mean ([^?]+)\?\)", err)
    assert found and err.count("\n") == 1, err
    return found.group(1)


@pytest.mark.parametrize("name", ["stereographic", "equisolid", "orthographic"])
def test_a_fisheye_mapping_named_alone_is_offered_the_fisheye(tmp_path, capsys, name):
    spec = _offered(capsys, ["warp", str(tmp_path / "in.exr"), "-o", str(tmp_path / "o.exr"), "--to", name])
    assert spec == f"fisheye:mapping={name}"
    n = 512
    lens = make_lens(f"{spec},fov=170", (n, n))
    x, y = 400.25, 130.5  # a point off both axes, inside the image circle
    d, ok = lens.pixel_to_dir(np.array([[x, y]]))
    f_half = np.radians(85.0)
    r = np.hypot(x - n / 2, y - n / 2) / (n / 2)  # radius in half image widths: 1 at the rim (fov / 2)
    theta = {"stereographic": 2 * np.arctan(r * np.tan(f_half / 2)),  # r = 2 f tan(theta / 2)
             "equisolid": 2 * np.arcsin(r * np.sin(f_half / 2)),  # r = 2 f sin(theta / 2)
             "orthographic": np.arcsin(r * np.sin(f_half))}[name]  # r = f sin(theta)
    assert ok[0] and np.degrees(np.arccos(d[0, 2])) == pytest.approx(np.degrees(theta), abs=1e-9)


def test_a_longer_spelling_of_a_model_is_offered_the_model(tmp_path, capsys):
    spec = _offered(capsys, ["warp", str(tmp_path / "in.exr"), "-o", str(tmp_path / "o.exr"),
                             "--to", "equirectangular"])
    assert spec == "equirect"
    w, h = 64, 32
    d, _ = make_lens(spec, (w, h)).pixel_to_dir(np.array([[48.5, 8.5]]))
    lon, lat = (2 * 48.5 / w - 1) * np.pi, (1 - 2 * 8.5 / h) * np.pi / 2  # phi = (2x/W - 1) pi, up positive
    assert np.arctan2(d[0, 0], d[0, 2]) == pytest.approx(lon, abs=1e-12)
    assert np.arcsin(d[0, 1]) == pytest.approx(lat, abs=1e-12)


def test_a_name_like_nothing_is_offered_nothing(tmp_path, capsys):
    assert main(["warp", str(tmp_path / "in.exr"), "-o", str(tmp_path / "o.exr"), "--to", "zzzz"]) == 2
    assert "did you mean" not in capsys.readouterr().err
