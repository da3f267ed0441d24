"""``lenslab camera convert --model opencv`` fits the tangential terms p1, p2 only when ``--free`` names them
(docs/cameras.md: "tangential and thin prism terms only when named")."""

from __future__ import annotations

import pytest

from lenslab.calibfiles import read_lens
from lenslab.cli.main import main

#: an OpenCV camera with tangential distortion (160 x 120); its values are what a fit that frees p1, p2 recovers
SOURCE = ("opencv:fx=125.0,fy=125.0,cx=79.5,cy=59.5,k1=-0.12,k2=0.03,p1=0.0015,p2=-0.001,"
          "width=160,height=120")


def convert(tmp_path, capsys, *extra):
    out = tmp_path / f"cam{len(extra)}.toml"
    code = main(["camera", "convert", SOURCE, "-o", str(out), "--model", "opencv", "--aim", "100", *extra])
    text = capsys.readouterr().out
    assert code == 0, text
    return read_lens(str(out))


def test_p1_p2_stay_zero_unless_named(tmp_path, capsys):
    cam = convert(tmp_path, capsys)
    assert cam.p1 == 0.0 and cam.p2 == 0.0  # fixed at zero, as the docs promise


def test_p1_p2_are_fitted_when_named(tmp_path, capsys):
    cam = convert(tmp_path, capsys, "--free", "fx,fy,cx,cy,k1,k2,k3,p1,p2")
    # the same model as the source: the fit recovers its tangential terms (1e-5: far below 0.001, and the
    # conversion's own stopping tolerance leaves less)
    assert cam.p1 == pytest.approx(0.0015, abs=1e-5) and cam.p2 == pytest.approx(-0.001, abs=1e-5)
