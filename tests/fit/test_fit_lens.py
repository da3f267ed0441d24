"""Lens to lens fits: exact self-recovery, division model as Brown, mapping discovery, impossible fits."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.errors import FitError
from lenslab.fit import fit_lens
from lenslab.lenses import REGISTRY, make_lens

SIZE = (256, 192)

# (true lens, perturbed start given as the model spec, fitted parameters): each model declares its own
# (``fit_examples``), so a new model is fitted here with no edit
SELF_FITS = [case for entry in REGISTRY.entries() for case in entry.capabilities["fit_examples"]]


@pytest.mark.parametrize("truth,start,free", SELF_FITS, ids=[c[0] for c in SELF_FITS])
def test_a_model_fitted_to_itself_recovers_its_parameters(truth, start, free):
    source = make_lens(truth, SIZE)
    fit = fit_lens(source, start, free=free, global_start=None)  # local search only, from the perturbed start
    want, got = source.param_values(), fit.lens.param_values()
    for name in free.split(","):
        # the search stops at 1e-10 of each range (degrees or coefficients): 1e-7 is exact recovery
        assert got[name] == pytest.approx(want[name], abs=1e-7), name
    # and the mapping with it: a millionth of a pixel
    assert fit.ok and fit.max < 1e-6 and fit.rms <= fit.max
    assert fit.unseen_fraction == 0.0


@settings(max_examples=12, deadline=None)
@given(st.sampled_from(["equidistant", "equisolid", "stereographic", "orthographic"]),
       st.floats(0.2, 0.95), st.floats(-0.2, 0.2))
def test_any_fisheye_is_recovered_from_a_perturbed_start(mapping, frac, perturb):
    limit = {"equidistant": 360.0, "equisolid": 360.0, "stereographic": 300.0, "orthographic": 180.0}[mapping]
    fov = frac * limit
    start = min(max(fov * (1 + perturb), 1.0), limit)
    source = make_lens(f"fisheye:fov={fov!r},mapping={mapping}", (96, 96))
    fit = fit_lens(source, f"fisheye:fov={start!r},mapping={mapping}", free="fov", global_start=None,
                   report_grid=49)
    assert fit.lens.fov == pytest.approx(fov, abs=1e-7)  # as above: exact recovery
    assert fit.max < 1e-6


def test_every_model_with_numeric_parameters_has_a_self_fit():
    covered = {make_lens(t, SIZE).name for t, _, _ in SELF_FITS}
    numeric = {name for name, cls in REGISTRY.items() if any(p.kind is float for p in cls.params)}
    assert numeric <= covered, f"add a self-fit case for {sorted(numeric - covered)}"


@pytest.mark.parametrize("k1", [-0.03, 0.03])
def test_division_model_as_brown_is_within_five_hundredths_of_a_pixel(k1):
    source = make_lens(f"distortion:k1={k1},k2=0,fov=60", (1024, 768))
    corner = float(np.hypot(1.0, 768 / 1024))
    assert source.r_fold > corner  # the division model is monotonic over the whole image
    fit = fit_lens(source, "brown")
    brown = fit.lens
    assert brown.name == "brown" and brown.ru_fold > 1.5 * corner  # and so is the fitted polynomial
    # Brown's k1 matches the division k1 to first order (r_d = r_u (1 + k1 r_d^2) ...)
    assert brown.k1 == pytest.approx(k1, rel=0.05)
    # the division model's inverse is a series in r_u whose r^7 and higher terms the Brown polynomial
    # lacks: for |k1| = 0.03 they leave about 0.02 px at the corners of a 1024-pixel-wide image
    assert fit.max < 0.05, fit.report()
    assert fit.rms < 0.01 and fit.ok


def test_an_unknown_fisheye_mapping_is_found():
    source = make_lens("fisheye:fov=190,mapping=equisolid", (128, 128))
    fit = fit_lens(source, "fisheye", report_grid=65)
    assert fit.lens.mapping == "equisolid"
    assert fit.lens.fov == pytest.approx(190, abs=1e-7)  # exact model: exact recovery (see above)
    assert len(fit.tried) == 4 and fit.ok
    others = [rms for spec, rms in fit.tried if "equisolid" not in spec]
    assert min(others) > 1.0  # every other mapping is visibly off: more than a pixel RMS


def test_an_impossible_fit_reports_a_large_residual_and_why():
    source = make_lens("fisheye:fov=360", (128, 128))
    fit = fit_lens(source, "perspective", report_grid=65)  # never raises for a poor fit
    assert not fit.ok
    assert fit.max > 100  # px: rays behind the camera are nowhere near any perspective pixel
    # half the sphere and more lies 90 deg or further off axis: a perspective sees none of it
    assert fit.unseen_fraction > 0.5
    reason = fit.reason()
    assert "does not see" in reason
    assert float(re.search(r"some are ([\d.]+) deg from the axis", reason).group(1)) > 170
    report = "\n".join(fit.report())
    assert "NOT A GOOD FIT" in report and "OK" not in report.split("verdict:")[1]


def test_a_poor_but_possible_fit_is_not_called_good():
    # pincushion is not a perspective at any fov: the fit is the best compromise, and says so
    fit = fit_lens(make_lens("pincushion:k1=0.2,fov=90", (128, 128)), "perspective", report_grid=65)
    assert not fit.ok and fit.max > 0.5 and "above the tolerance" in fit.reason()


def test_fits_are_deterministic():
    source = make_lens("barrel:k1=-0.1,k2=0.01,fov=80", (200, 150))
    a = fit_lens(source, "brown", report_grid=65, global_start=None)  # global starts: test_fit_optimize
    b = fit_lens(source, "brown", report_grid=65, global_start=None)
    assert a.lens.spec() == b.lens.spec()
    assert np.array_equal(a.residuals.r, b.residuals.r)
    assert a.optimizer.evaluations == b.optimizer.evaluations


def test_pixel_space_fit_agrees_with_direction_space_on_an_exact_model():
    source = make_lens("distortion:k1=-0.12,k2=0.02,fov=75", SIZE)
    fit = fit_lens(source, "distortion:k1=-0.05,k2=0,fov=65", free="k1,k2,fov", space="pixel")
    assert fit.lens.k1 == pytest.approx(-0.12, abs=1e-7) and fit.max < 1e-6


def test_nothing_free_reports_the_distance_between_two_specs():
    fit = fit_lens(make_lens("perspective:fov=70", SIZE), "perspective:fov=80")
    assert fit.free == () and not fit.ok
    # 10 degrees of fov moves the edge of a 256-pixel image by tens of pixels
    assert 10 < fit.max < 100


@pytest.mark.parametrize("model,kw,match", [
    ("nosuchlens", {}, "unknown lens model"),
    ("perspective", {"free": "focal"}, "no such parameter"),
    ("fisheye", {"free": "mapping"}, "not a real number"),
    ("perspective", {"bounds": "k1=0:1"}, "not fitted"),
    ("perspective", {"bounds": "fov=10"}, "NAME=LOW:HIGH"),
    ("perspective", {"space": "angle"}, "residual space"),
])
def test_set_up_errors_say_what_to_do(model, kw, match):
    with pytest.raises(FitError, match=match):
        fit_lens(make_lens("perspective:fov=70", SIZE), model, **kw)
