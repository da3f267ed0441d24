"""A lens's printed spec (``lenslab info``, the tracer's lines, ``lenslab stmap``'s header) is one a user would
type: parameters at a value that means "derived from the others" (``vfov=0``: square pixels) are left out, and the
text parses back to the same lens. A cylinder's ``vfov=0.5`` was printed as ``fov=360.5`` (a text replacement)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens


@pytest.mark.parametrize("spec, printed", [
    ("perspective", "perspective:fov=90"),
    ("perspective:fov=70", "perspective:fov=70"),
    ("swirl", "swirl:amount=6,base=perspective,fov=90"),
    ("barrel:k1=-0.3", "barrel:k1=-0.3,k2=0,base=perspective,fov=90"),
    ("perspective:dfov=100.123456", "perspective:dfov=100.123456"),
    ("cylindrical:vfov=0.5", "cylindrical:fov=360,vfov=0.5"),
    ("mercator:fov=200,vfov=0.25", "mercator:fov=200,vfov=0.25"),
])
def test_printed_spec(spec, printed):
    assert make_lens(spec, (64, 32)).spec() == printed


def test_a_thin_cylinder_read_back_keeps_its_latitude_range():
    """The top edge of a cylindrical image of vfov 0.5 is at latitude 0.25 degrees: y = tan(lat) at unit radius,
    so the direction through the top edge's centre has dy / hypot(dx, dz) = tan(0.25 deg) (camera y up)."""
    lens = make_lens(make_lens("cylindrical:vfov=0.5", (64, 32)).spec(), (64, 32))
    d = lens.pixel_to_dir(np.array([[32.0, 0.0]]))[0][0]
    assert d[1] / math.hypot(d[0], d[2]) == pytest.approx(math.tan(math.radians(0.25)), rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(fov=st.floats(1.0, 179.0), vfov=st.one_of(st.just(0.0), st.floats(0.01, 179.0)),
       name=st.sampled_from(["perspective", "fisheye", "cylindrical", "mercator", "swirl"]))
def test_the_printed_spec_parses_back_to_the_same_lens(fov, vfov, name):
    if name == "fisheye":  # one of fov and vfov
        spec = f"{name}:vfov={vfov!r}" if vfov else f"{name}:fov={fov!r}"
    else:
        spec = f"{name}:fov={fov!r}" + (f",vfov={vfov!r}" if vfov else "")
    lens = make_lens(spec, (64, 48))
    text = lens.spec()
    assert "vfov=0," not in text + "," and "dfov=0," not in text + ","
    assert make_lens(text, (64, 48)) == lens
