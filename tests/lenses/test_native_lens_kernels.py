"""Each compiled lens kernel (C++, ``lenslab.cxx_kernels``) against its NumPy reference
(:mod:`lenslab.lenses.formulas.reference`, composed from the NumPy formulas and the NumPy Newton solve), on
directions and pixels drawn by hypothesis with the extremes mixed in: the poles, the seam (``x = -0.0`` and
``+0.0`` behind the camera), the axis and the back pole, grazing and tiny directions, fields of view near 0 and
360 degrees, the fold-over of a distortion, and zero, NaN and infinite directions (invalid).

The kernels run exactly as the lens models call them: a recorder stands in for the extension module, passes
each call on and keeps its arguments and outputs, and each recorded call is then replayed through the reference.

Tolerances: the closed forms are the same operations in the same order, built without fused multiply-adds, so
they differ only by the last bits of libm's transcendental functions (a few ulps of the largest term): 1e-9 px
on images of at most 4096 px is 1e3 times that and still 1e6 times below what a float32 map resolves. The
solved sides stop within the solver's tolerance (1e-13 in normalised units, about 1e-10 px at these focal
lengths) from starting guesses that round differently (``np.interp`` against the kernels' own interpolation),
so they are held to 1e-7 px and 1e-9 of a unit ray.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lenslab.lenses.core.native as native
from lenslab.lenses import make_lens
from lenslab.lenses.formulas import kinds, reference
from lenslab.lenses.formulas.solve import DIVISION, OCAM, kernel_settings
from lenslab.lenses.core.native import project_kernel

NAN, INF = math.nan, math.inf
#: directions at the extremes (any length: the kernels normalise)
EXTREME_DIRS = [
    (0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0),  # poles, axis, back pole
    (-0.0, 0.0, -1.0), (-1e-300, 0.0, -1.0), (1e-300, 0.0, -1.0), (-1e-12, 0.3, -1.0),  # the seam, both sides
    (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (1.0, 0.0, 1e-17), (1e-9, 1e-9, 1.0), (1e-300, 1e-300, 1e-300),
    (1e300, -1e300, 1e300), (3.0, 4.0, 12.0), (0.0, 0.0, 0.0), (NAN, 0.0, 1.0), (0.0, INF, 1.0), (-INF, 0.0, 0.0),
]
coord = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False, allow_subnormal=False)
DIRS = st.lists(st.one_of(st.sampled_from(EXTREME_DIRS), st.tuples(coord, coord, coord)), min_size=1,
                max_size=48).map(lambda rows: np.array(rows, dtype=np.float64))
#: pixels: anywhere in and around a 4096-wide image, its corners and centre, and non-finite ones
EXTREME_PIXELS = [(0.0, 0.0), (4096.0, 4096.0), (2048.0, 2048.0), (2048.0, 1024.0), (-1e6, 3.0), (1e300, 1.0),
                  (NAN, 5.0), (3.0, INF), (-INF, -INF)]
pix = st.floats(-200.0, 4300.0, allow_nan=False, allow_infinity=False)
PIXELS = st.lists(st.one_of(st.sampled_from(EXTREME_PIXELS), st.tuples(pix, pix)), min_size=1,
                  max_size=48).map(lambda rows: np.array(rows, dtype=np.float64))

HYP = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])

#: how many of each kernel's trailing arguments are outputs
OUTPUTS = {"distort_points": 3}
SOLVED = {"division_unbend", "brown_bend", "tan_fisheye_dir_to_uv", "calibrated_unproject", "ocam_project"}


class Recorder:
    """Stands in for the extension module: runs each kernel and keeps (name, inputs, outputs)."""

    def __init__(self, module):
        self.module, self.calls = module, []

    def __getattr__(self, name):
        fn = getattr(self.module, name)
        if not callable(fn):
            return fn

        def run(*args):
            result = fn(*args)
            n = OUTPUTS.get(name, 2)
            self.calls.append((name, args[:-n], [np.array(a, copy=True) for a in args[-n:]]))
            return result
        return run


@pytest.fixture
def recorder(monkeypatch):
    rec = Recorder(native.lens_kernels())
    monkeypatch.setattr(native, "lens_kernels", lambda: rec)  # every model asks for it at the call
    return rec


def check_calls(calls, expected: set[str]):
    """Replay every recorded call through its reference; the kernels named in ``expected`` must have run."""
    assert expected <= {name for name, _, _ in calls}
    for name, inputs, outputs in calls:
        want = getattr(reference, name)(*inputs)
        tol = 1e-7 if name in SOLVED else 1e-9
        if name == "calibrated_unproject":
            tol = 1e-9  # unit rays
        *values, ok = outputs
        *ref_values, ref_ok = want
        np.testing.assert_array_equal(ok.reshape(-1), ref_ok.reshape(-1), err_msg=f"{name}: validity")
        for got, ref in zip(values, ref_values):
            got, ref = got.reshape(len(ok), -1), np.asarray(ref).reshape(len(ok), -1)
            assert np.all(got[~ok] == 0.0), f"{name}: non-zero output where invalid"
            np.testing.assert_allclose(got[ok], ref[ok], rtol=0, atol=tol, err_msg=name)


def test_the_kernels_dispatch_on_the_python_codes():
    codes = native.lens_kernels().lens_codes
    for name in ("RECTILINEAR", "EQUIRECTANGULAR", "CYLINDRICAL", "EQUIDISTANT", "EQUISOLID", "STEREOGRAPHIC",
                 "ORTHOGRAPHIC", "THOBY", "UNIFIED", "DOUBLE_SPHERE", "EUCM", "FOV", "EQUAL_AREA_CYLINDRICAL",
                 "MERCATOR"):
        assert codes[name] == getattr(kinds, name)
    assert (codes["DIVISION"], codes["OCAM"]) == (DIVISION, OCAM)
    assert native.lens_kernels().THOBY_K == (kinds.THOBY_K1, kinds.THOBY_K2)


EQUIRECTS = ["equirect", "equirect:lon_min=-90,lon_max=90,lat_min=-45,lat_max=60",
             "equirect:lon_min=-0.01,lon_max=0.01,lat_min=-0.005,lat_max=0.005",  # fov near 0
             "equirect:lon_min=-179.99,lon_max=180,lat_min=-90,lat_max=90",  # near 360, no wrap
             "equirect:lat_min=-90,lat_max=0"]  # a full turn, half the sphere


@pytest.mark.parametrize("spec", EQUIRECTS)
@HYP
@given(d=DIRS)
def test_equirect_pixel_kernel_matches_its_reference_and_the_model(spec, d):
    lens = make_lens(spec, (4096, 2048))
    kern = lens.pixel_kernel()
    xy, ok = project_kernel(kern, d)
    want, want_ok = reference.equirect_pixels(d, kern.params)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(xy, want, rtol=0, atol=1e-9)
    model, model_ok = lens.dir_to_pixel(d)  # the model's own NumPy dir_to_pixel
    np.testing.assert_array_equal(ok, model_ok)
    np.testing.assert_allclose(xy, model, rtol=0, atol=1e-9)


WHOLE = [("perspective:fov=90", (640, 480)), ("perspective:fov=0.01", (64, 64)),  # fov near 0
         ("perspective:fov=179.99", (512, 512)), ("perspective:fov=120,vfov=60", (800, 400)),
         ("perspective:dfov=100", (600, 400)), ("hammer", (800, 400)), ("hammer", (512, 512)),
         ("tiled:2x2", (800, 600)), ("tiled:3x1", (900, 200)),
         # the fisheye mappings, the little planet, the cylinders, the Brown-distorted pinhole and two fisheyes back to
         # back (lens_pixels.cpp;
         # their published formulas in test_native_projection_pixels.py)
         ("fisheye:fov=180,mapping=stereographic", (512, 512)), ("fisheye:fov=350,mapping=stereographic", (640, 480)),
         ("fisheye:fov=0.01,mapping=stereographic", (64, 64)), ("fisheye:fov=180,mapping=equidistant", (512, 512)),
         ("fisheye:fov=360,mapping=equidistant", (512, 512)), ("fisheye:fov=360,mapping=equisolid", (512, 384)),
         ("fisheye:fov=180,mapping=orthographic", (800, 600)), ("fisheye:dfov=180", (800, 533)),
         ("fisheye:vfov=150,mapping=equisolid,cx=0.05,cy=-0.02", (800, 533)),
         ("little-planet", (512, 512)), ("little-planet:fov=359.9", (640, 400)), ("little-planet:fov=0.01", (64, 64)),
         ("cylindrical", (1024, 512)), ("cylindrical:fov=180,vfov=120", (1024, 512)), ("cylindrical:fov=0.01", (64, 64)),
         ("cylindrical-equal-area", (1024, 326)), ("cylindrical-equal-area:vfov=180", (1024, 512)),
         ("mercator", (512, 512)), ("mercator:fov=200,vfov=150", (1024, 512)), ("mercator:fov=359.99", (600, 700)),
         ("mercator:vfov=179.999", (256, 256)),
         ("brown:k1=-0.05,fov=90", (640, 480)), ("brown:k1=-0.3,fov=120", (512, 512)),  # folds inside the image
         ("brown:k1=0.1,k2=0.05,fov=0.5", (64, 48)), ("brown:k1=0.1,k2=-0.3,fov=100,vfov=60", (800, 400)),
         ("dual-fisheye:fov=190", (1024, 512)), ("dual-fisheye:fov=180,mapping=equisolid,front=right", (1024, 512)),
         ("dual-fisheye:fov=200,mapping=stereographic", (1001, 480)),  # an odd width: halves of 500.5 px
         ("dual-fisheye:fov=170,mapping=orthographic", (800, 400)), ("dual-fisheye:fov=360", (800, 400)),
         ("dual-fisheye:fov=0.01", (64, 32)), ("sinusoidal", (800, 400)), ("sinusoidal", (300, 700)),
         ("pannini", (800, 400)), ("pannini:fov=170,d=2,vcomp=0.5", (512, 512)), ("pannini:fov=100,d=0", (300, 700)),
         ("pannini:fov=0.01", (64, 64)), ("pannini:fov=239.9,d=0.5,vcomp=1", (800, 400)),
         ("swirl:amount=6", (800, 400)), ("swirl:amount=-3,fov=150", (512, 512)), ("swirl:amount=0", (300, 700)),
         ("swirl:amount=100,fov=0.01", (64, 64))]


def numpy_steps(lens):
    """``lens`` with its compiled kernel (and its tiles') switched off: its NumPy dir_to_pixel runs."""
    lens.pixel_kernel = lambda: None
    for tile in getattr(lens, "tile_list", ()):
        if tile is not None:
            tile.lens.pixel_kernel = lambda: None
    return lens


@pytest.mark.parametrize("spec,size", WHOLE)
@HYP
@given(d=DIRS)
def test_whole_image_kernels_match_the_models_numpy_steps(spec, size, d):
    """The whole-image kernels (perspective, Hammer, sinusoidal, Pannini, tiled, fisheye, little planet,
    dual fisheye, cylinders, Brown, swirl) are the NumPy
    steps of Lens.dir_to_pixel (normalise, dir_to_uv, uv_to_pixel, snap_to_image; for a grid, the first tile that
    sees the direction): those steps, run with the kernels switched off, are their reference."""
    lens = make_lens(spec, size)
    kern = lens.pixel_kernel()
    assert kern is not None
    xy, ok = project_kernel(kern, d)
    want, want_ok = numpy_steps(lens).dir_to_pixel(d)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(xy, want, rtol=0, atol=1e-9)


D2P = {
    "pincushion:k1=0.3,k2=0.05,fov=90": {"division_unbend"},
    "barrel:k1=-0.3,fov=90": {"division_unbend"},  # folds over inside the image
    "barrel:k1=-0.3,fov=0.5": {"division_unbend"},  # fov near 0
    "tan-fisheye:fov=120": {"tan_fisheye_dir_to_uv"},
    "tan-fisheye:fov=170": {"tan_fisheye_dir_to_uv"},  # folds back past 144.7
    "opencv:fx=600,fy=600,cx=511.5,cy=511.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=-0.01,k4=0.02,k5=0.001,"
    "k6=0.0005,s1=0.001,s2=-0.0002,s3=0.0007,s4=0.0001,width=1024,height=1024": {"calibrated_project"},
    "opencv:fx=300,fy=300,cx=511.5,cy=511.5,k1=-0.4,width=1024,height=1024": {"calibrated_project"},  # fold
    "kannala-brandt:fx=250,fy=250,cx=511.5,cy=511.5,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,width=1024,height=1024":
        {"calibrated_project"},
    "omnidir:fx=400,fy=400,cx=511.5,cy=511.5,xi=1.6,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,width=1024,height=1024":
        {"calibrated_project"},
    "double-sphere:fx=200,fy=200,cx=511.5,cy=511.5,xi=-0.2,alpha=0.6,width=1024,height=1024": {"calibrated_project"},
    "eucm:fx=200,fy=200,cx=511.5,cy=511.5,alpha=0.6,beta=1.1,width=1024,height=1024": {"calibrated_project"},
    "devernay-fov:fx=400,fy=400,cx=511.5,cy=511.5,omega=0.9,width=1024,height=1024": {"calibrated_project"},
    "ocam:pol=-250 0 0.002,xc=511.5,yc=511.5,width=1024,height=1024": {"ocam_project"},
}
P2D = {
    "brown:k1=-0.05,fov=90": {"brown_bend"},
    "brown:k1=-0.3,fov=120": {"brown_bend"},  # folds over inside the image
    **{spec: {"calibrated_unproject"} for spec in D2P if spec.split(":")[0] in
       ("opencv", "kannala-brandt", "omnidir", "double-sphere", "eucm", "devernay-fov")},
}


@pytest.mark.parametrize("spec", sorted(D2P))
@HYP
@given(d=DIRS)
def test_dir_to_pixel_kernels_match_their_references(spec, d, recorder):
    recorder.calls.clear()
    make_lens(spec, (1024, 1024)).dir_to_pixel(d)
    check_calls(recorder.calls, D2P[spec])


@pytest.mark.parametrize("spec", sorted(P2D))
@HYP
@given(xy=PIXELS)
def test_pixel_to_dir_kernels_match_their_references(spec, xy, recorder):
    recorder.calls.clear()
    make_lens(spec, (4096, 4096)).pixel_to_dir(xy)
    check_calls(recorder.calls, P2D[spec])


@HYP
@given(x=st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=48))
def test_distortion_kernel_matches_its_reference(x, recorder):
    recorder.calls.clear()
    lens = make_lens(next(s for s in D2P if s.startswith("opencv:fx=600")), (1024, 1024))
    pts = np.array(x)
    lens.distortion.apply(pts, pts[::-1].copy())  # up to and past the fold, with tangential and prism terms
    check_calls(recorder.calls, {"distort_points"})


LENSFUN_KINDS = [kinds.RECTILINEAR, kinds.EQUIRECTANGULAR, kinds.CYLINDRICAL, kinds.EQUIDISTANT, kinds.EQUISOLID,
                 kinds.STEREOGRAPHIC, kinds.ORTHOGRAPHIC, kinds.THOBY]


@pytest.mark.parametrize("kind", LENSFUN_KINDS)
@HYP
@given(d=DIRS, coeffs=st.sampled_from([(1.0,), (1.005, 0.005, -0.02, 0.01), (0.98, 0.0, 0.02)]))
def test_lensfun_kernel_matches_its_reference(kind, d, coeffs):
    xy, ok = np.empty((len(d), 2)), np.empty(len(d), dtype=bool)
    args = (d, kind, 700.0 / 1200.0, np.array(coeffs), 1.8, 300.5, 200.5, 1.0 / 1200.0)
    native.lens_kernels().lensfun_dir_to_pixel(*args, xy, ok)
    check_calls([("lensfun_dir_to_pixel", args, [xy, ok])], {"lensfun_dir_to_pixel"})


@pytest.mark.parametrize("name", ["Sigma 10mm f/2.8 EX DC Fisheye HSM", "Samyang 12mm f/2.8 Fish-Eye ED AS NCS"])
@HYP
@given(d=DIRS)
def test_lensfun_profiles_run_the_kernel_as_referenced(name, d, recorder):
    pytest.importorskip("lensfunpy")  # the profiles' database (a declared test dependency)
    recorder.calls.clear()
    make_lens(f'lensfun:lens="{name}"', (600, 400)).dir_to_pixel(d)
    check_calls(recorder.calls, {"lensfun_dir_to_pixel"})


def test_solver_settings_are_the_numpy_solves():
    tol, res_tol, rel_ulps, max_iter = kernel_settings()
    assert tol == 1e-13 and max_iter == 100 and res_tol == 1e-11 and rel_ulps == 8 * np.finfo(float).eps


def test_no_lens_needs_numba():
    """Every lens of the benchmark and a lensfun profile map pixels and directions both ways, and ask for their
    compiled kernels, in a fresh process that never imports numba: nothing is compiled on a machine's first use."""
    import subprocess
    import sys

    code = (
        "import sys, numpy as np\n"
        "from lenslab.bench.lenses import DEFAULT_SPECS\n"
        "from lenslab.lenses import make_lens\n"
        "xy = np.random.default_rng(0).uniform(-2, 66, (500, 2))\n"
        "specs = list(DEFAULT_SPECS) + ['lensfun:lens=\"Sigma 10mm f/2.8 EX DC Fisheye HSM\"']\n"
        "for s in specs:\n"
        "    lens = make_lens(s, (64, 64))\n"
        "    d, ok = lens.pixel_to_dir(xy)\n"
        "    lens.dir_to_pixel(d)\n"
        "    lens.pixel_kernel()\n"
        "print('numba' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
