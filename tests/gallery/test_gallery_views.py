"""The demo's lens views (gallery/views.py): named in words, typed as a user would, each in a frame that
fits its lens. The frames are checked against closed-form areas: an image that is a disc or an ellipse
inscribed in its frame covers pi/4 of it, and a little planet whose diagonal spans 300 degrees covers
all of it (its corners are 150 degrees from the axis, inside the stereographic's 180)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import lenslab
from gallery.views import MODEL_VIEWS, NOT_A_VIEW, has_defaults, lens_views
from lenslab.lenses import REGISTRY

SIDE = 96
PANO = lenslab.Camera.from_spec("equirect", (256, 128))


def coverage(view: dict) -> float:
    cam = lenslab.Camera.from_spec(view["spec"], view["size"], **view["pose"])
    _, alpha = lenslab.warp(np.ones((128, 256, 1), np.float32), PANO, cam, samples=16)
    return float(alpha.mean())


def by_spec(spec: str) -> dict:
    return next(v for v in lens_views(SIDE) if v["spec"] == spec)


def test_every_model_has_a_view_named_in_words():
    views = lens_views(SIDE)
    names = [v["name"] for v in views]
    assert len(set(names)) == len(names)  # a name is a file name and a record's key
    shown = {v["spec"].partition(":")[0] for v in views}
    assert shown >= {m for m in REGISTRY if has_defaults(m)} - set(NOT_A_VIEW)
    for v in views:
        assert "=" not in v["name"] and "(its defaults)" not in v["name"], v["name"]
        assert len(v["spec"]) <= 90, v["spec"]  # what a user would type, never every parameter spelled out
    assert set(MODEL_VIEWS) <= set(REGISTRY)


def test_optics_is_shown_with_its_faults_not_as_a_plain_perspective():
    """A uniform sky through the optics view falls off as cos^4 of the angle from the axis (the
    vignetting its spec names), where the plain perspective it is built on stays uniform."""
    spec = MODEL_VIEWS["optics"][1]
    sky = np.ones((128, 256, 3), np.float32)
    faulty, _ = lenslab.warp(sky, PANO, lenslab.Camera.from_spec(spec, (SIDE, SIDE)))
    plain, _ = lenslab.warp(sky, PANO, lenslab.Camera.from_spec("perspective:fov=100", (SIDE, SIDE)))
    np.testing.assert_allclose(plain, 1.0, atol=1e-6)
    u = 1.0 - 1.0 / SIDE  # the corner pixel's centre, in half widths from the image centre
    theta = math.atan(math.hypot(u, u) * math.tan(math.radians(50.0)))
    assert faulty[0, 0, 1] == pytest.approx(math.cos(theta) ** 4, rel=1e-3)  # green: no colour shift
    assert faulty[SIDE // 2, SIDE // 2, 1] == pytest.approx(1.0, abs=1e-3)


@pytest.mark.parametrize("spec, area", [
    ("fisheye:dfov=300,mapping=stereographic", 1.0),   # the little planet fills its square
    ("little-planet", math.pi / 4),                    # the model's disc, inscribed in a square
    ("hammer", math.pi / 4),                           # an ellipse inscribed in a 2:1 frame
    ("dual-fisheye", math.pi / 4),                     # two discs, each inscribed in half the frame
    ("cylindrical:fov=360", 1.0),
    ("eac", 1.0),
])
def test_frames_fit_their_lens(spec, area):
    # 16 samples per pixel: the rim's pixels are covered in proportion, so the mean is the area to
    # about one pixel's share of the rim (4 / SIDE of the frame at most)
    assert coverage(by_spec(spec)) == pytest.approx(area, abs=2.0 / SIDE)
