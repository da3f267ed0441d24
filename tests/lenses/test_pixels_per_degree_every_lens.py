"""Every registered lens reports its own angular resolution (``pixels_per_degree``), and a warp without ``--size``
takes its rows of 180 degrees from it: the rows of the lens's first piece (a cube face, a tile, an eye, the whole
image) over the angle its middle column spans where it has rays (docs/guide/360.md). Where the resolution varies
(a perspective view, a fisheye that is not equidistant) that is the mean down that column.

The expected angles are computed here from each model's documented geometry (its field of view, its formula and
its pixel size), in float64, independently of the lens code; a model with no case here fails
:func:`test_every_registered_lens_has_a_case`, so a new lens must say what its resolution is.
"""

from __future__ import annotations

from math import asin, atan, atan2, cos, degrees, hypot, pi, radians, sin, sqrt, tan, tanh

import numpy as np
import pytest

from lenslab.jobs.warp.cameras import source_rows
from lenslab.lenses import REGISTRY, make_lens

#: the lens sums its column's angles as chords over 4096 steps (exact on a great circle, 1e-8 off a swirl's curve),
#: ending 1e-6 px short of the bottom edge (the next piece's top): 1e-9 of the span where the angle is smooth there
REL = 1e-6
#: where a model's angle rises like a square root at the edge (a mirror ball's rim, the globe's) the missing 1e-6 px
#: are up to 3e-5 of the span
REL_STEEP = 1e-4
#: a column that ends inside the image (an image circle's edge, a model's fold) loses the step across that end,
#: up to 1 of 4096 steps at each end: 5e-4 of the rows
REL_CIRCLE = 1e-3


def _root(f, lo: float, hi: float) -> float:
    """The root of an increasing ``f`` in [lo, hi], by bisection to float64."""
    assert f(lo) < 0 < f(hi), "no root in the bracket: the edge is outside the model's domain"
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def _pinhole(r_u: float) -> float:
    """Span of a pinhole's middle column whose edge is ``r_u`` focal lengths from the axis, both ways."""
    return 2 * degrees(atan(r_u))


def _scaled(focal_1000: float, rows: int) -> float:
    """A calibrated model's default focal (in pixels of its 1000 x 1000 calibration image) in this image's pixels."""
    return focal_1000 * rows / 1000.0


def _swirl_span(amount: float, samples: int = 400001) -> float:
    """The middle column of ``swirl`` (base perspective:fov=90) on the sphere: ``(u, v) = (0, v)`` turned by
    ``|v| amount`` about the centre, then ``d ~ (u', v', 1)``; its length summed over fine great-circle arcs."""
    v = np.linspace(-1.0, 1.0, samples)
    rho, alpha = np.abs(v), np.where(v >= 0, pi / 2, -pi / 2)
    d = np.stack([rho * np.cos(alpha + rho * amount), rho * np.sin(alpha + rho * amount), np.ones_like(v)], -1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return degrees(float(np.sum(2 * np.arcsin(0.5 * np.linalg.norm(np.diff(d, axis=0), axis=-1)))))


def _tan_fisheye(fov: float) -> float:
    """``psi(1) = atan2(sin t, cos t)`` with ``t = tan(F)`` at the rim (t < pi: no fold), both ways."""
    t = tan(radians(fov) / 2)
    return 2 * degrees(atan2(sin(t), cos(t)))


def _double_sphere(m_edge: float, xi: float, alpha: float) -> float:
    """Angle from the axis of the ray at normalised radius ``m_edge``, double sphere: ``m = sin a / (alpha d2 +
    (1 - alpha)(xi + cos a))``, ``d2 = |(sin a, xi + cos a)|`` (Usenko et al. 2018), both ways."""
    def m(a):
        d2 = sqrt(sin(a) ** 2 + (xi + cos(a)) ** 2)
        return sin(a) / (alpha * d2 + (1 - alpha) * (xi + cos(a))) - m_edge
    return 2 * degrees(_root(m, 0.0, 0.9 * pi))


def _eucm(m_edge: float, alpha: float, beta: float) -> float:
    """EUCM (Khomutenko et al. 2016): ``m = sin a / (alpha sqrt(beta sin^2 a + cos^2 a) + (1 - alpha) cos a)``."""
    def m(a):
        return sin(a) / (alpha * sqrt(beta * sin(a) ** 2 + cos(a) ** 2) + (1 - alpha) * cos(a)) - m_edge
    return 2 * degrees(_root(m, 0.0, 0.75 * pi))  # (rising up to 135 degrees for the parameters here)


def _brown_inverse(k1: float) -> float:
    """The undistorted radius whose Brown image ``r_u (1 + k1 r_u^2)`` is the edge's 1 (the smallest positive root)."""
    roots = np.roots([k1, 0.0, 1.0, -1.0])
    return float(min(r.real for r in roots if abs(r.imag) < 1e-12 and r.real > 0))


def _globe(distance: float) -> float:
    """``sin z = (h - sqrt(1 - r^2)) / (h/r + r/h)`` at the rim ``r = 1``, ``h = 1 + distance``, both ways."""
    h = 1.0 + distance
    return 2 * degrees(asin(h / (h + 1 / h)))


def _ocam_span(rows: int) -> float:
    """OCamCalib's default ``pol = -250 + 0.002 rho^2`` of a 1000-pixel image, in this image's pixels
    (``a0 s + a2 rho^2 / s``): the middle column's rim at ``rho = rows/2``, ``angle = atan2(rho, -pol(rho))``."""
    s = rows / 1000.0
    rho = rows / 2
    return 2 * degrees(atan2(rho, -(-250 * s + 0.002 / s * rho ** 2)))


def _pannini_span(fov: float, d: float, width: int, height: int) -> float:
    """``x = S sin phi``, ``y = S tan theta``, ``S = (d + 1) / (d + cos phi)``, the width spanning fov: the middle
    column (phi = 0, S = 1) reaches ``y = x_edge H/W``."""
    phi = radians(fov) / 2
    x_edge = (d + 1) / (d + cos(phi)) * sin(phi)
    return 2 * degrees(atan(x_edge * height / width))


def _lensfun_pinhole(focal_mm: float, crop: float, width: int, height: int) -> float:
    """lensfun's rectilinear projection without its corrections (``effects=none``) on a 3:2 sensor of ``crop``
    whose profile was calibrated there: the short side, between the outermost pixel centres (``height - 1``), is
    the sensor's (half the 36 x 24 mm diagonal over the crop factor, along a 3:2 diagonal); the column's edges
    lie half a pixel further out."""
    half_short_mm = hypot(36.0, 24.0) / 2 / crop / hypot(width - 1, height - 1) * (height - 1)
    return _pinhole(half_short_mm * height / (height - 1) / focal_mm)


def _fisheye(mapping: str, fov: float, r: float) -> float:
    """Angle from the axis at image radius ``r`` (1 at the half width), F = fov/2, both ways."""
    f = radians(fov) / 2
    a = {"equidistant": r * f, "equisolid": 2 * asin(r * sin(f / 2)), "stereographic": 2 * atan(r * tan(f / 2)),
         "orthographic": asin(r * sin(f))}[mapping]
    return 2 * degrees(a)


#: per model: ``(spec, (width, height), rows of the measured column that have rays, degrees they span, tolerance)``
CASES = {
    "ball": [("ball", (400, 400), 400, 360.0, REL_STEEP)],  # the back pole at the rim, above and below
    "barrel": [("barrel", (400, 400), 400, _pinhole(1 / (1 - 0.3)), REL)],  # r_u = r_d / (1 + k1 r_d^2), fov 90
    "brown": [("brown", (400, 400), 400, _pinhole(_brown_inverse(-0.05)), REL)],
    "cubemap": [("cubemap", (600, 400), 200, 90.0, REL), ("cubemap:layout=6x1", (1536, 256), 256, 90.0, REL),
                ("cubemap:layout=1x6", (256, 1536), 256, 90.0, REL)],
    "cylindrical": [("cylindrical", (800, 400), 400, 2 * degrees(atan(pi * 400 / 800)), REL),
                    ("cylindrical:fov=180,vfov=100", (600, 500), 500, 100.0, REL)],
    "cylindrical-equal-area": [("cylindrical-equal-area", (1257, 400), 400, 2 * degrees(asin(pi * 400 / 1257)), REL)],
    "devernay-fov": [("devernay-fov", (400, 400), 400, _pinhole(tan(0.5) / (2 * tan(0.25))), REL)],
    "distortion": [("distortion", (400, 400), 400, _pinhole(1 / 1.3), REL)],
    "division": [("division", (400, 400), 400, _pinhole(200 / _scaled(500, 400)), REL)],
    "double-sphere": [("double-sphere", (400, 400), 400, _double_sphere(200 / _scaled(250, 400), 0.0, 0.5), REL),
                      ("double-sphere:xi=0.1,alpha=0.5", (400, 400), 400,
                       _double_sphere(200 / _scaled(250, 400), 0.1, 0.5), REL)],
    "dual-fisheye": [("dual-fisheye", (800, 400), 400, 190.0, REL)],  # each lens's fov across its square half
    "eac": [("eac", (600, 400), 200, 90.0, REL), ("eac:pad=2", (606, 404), 404 // 2 - 4, 90.0, REL)],
    "equirect": [("equirect", (800, 400), 400, 180.0, REL),
                 ("equirect:lat_min=-45,lat_max=45", (800, 200), 200, 90.0, REL)],
    "eucm": [("eucm", (400, 400), 400, _eucm(200 / _scaled(250, 400), 0.5, 1.0), REL),
             ("eucm:alpha=0.5,beta=1.5", (400, 400), 400, _eucm(200 / _scaled(250, 400), 0.5, 1.5), REL)],
    "fb-barrel": [("fb-barrel", (1000, 400), 400, 90.0 / 0.99, REL)],  # the band: latitudes -45..45 over 0.99 H
    "fb-barrelsplit": [("fb-barrelsplit", (600, 400), 200, 90.0, REL)],  # the front half of the band
    "fisheye": [("fisheye", (400, 400), 400, 180.0, REL),
                ("fisheye:fov=180,mapping=equisolid", (400, 300), 300, _fisheye("equisolid", 180, 0.75), REL),
                ("fisheye:fov=200,mapping=stereographic", (400, 400), 400, _fisheye("stereographic", 200, 1), REL),
                ("fisheye:fov=180", (300, 400), 300, 180.0, REL_CIRCLE)],  # the circle spans 300 of 400 rows
    "fisheye624": [("fisheye624", (400, 400), 400, 2 * degrees(200 / _scaled(1000 / pi, 400)), REL)],
    "globe": [("globe", (400, 400), 400, _globe(180.0), REL_STEEP)],
    "half-equirect": [("half-equirect", (400, 400), 400, 180.0, REL)],
    "hammer": [("hammer", (800, 400), 400, 180.0, REL)],  # the 2:1 ellipse's height: the poles
    "kannala-brandt": [("kannala-brandt", (400, 400), 400, 2 * degrees(200 / _scaled(1000 / pi, 400)), REL)],
    # the Canon EF 50mm f/1.8 profile lenslab resolves was calibrated on a 1.613-crop, 3:2 sensor (lensfun's database)
    "lensfun": [("lensfun:lens=Canon EF 50mm f/1.8,crop=1.613,effects=none", (601, 401), 401,
                 _lensfun_pinhole(50.0, 1.613, 601, 401), REL)],
    "little-planet": [("little-planet", (400, 400), 400, _fisheye("stereographic", 270, 1), REL)],
    "mercator": [("mercator", (400, 400), 400, 2 * degrees(asin(tanh(pi))), REL)],
    "ocam": [("ocam", (400, 400), 400, _ocam_span(400), REL)],
    "octahedron": [("octahedron", (400, 400), 400, 180.0, REL)],  # (0, v, 1 - |v|): pole to pole
    "omnidir": [("omnidir", (400, 400), 400, 2 * degrees(2 * atan(200 / _scaled(500, 400))), REL)],  # m = tan(a/2)
    "opencv": [("opencv", (400, 400), 400, _pinhole(200 / _scaled(500, 400)), REL)],
    "opencv-fisheye": [("opencv-fisheye", (400, 400), 400, 2 * degrees(200 / _scaled(1000 / pi, 400)), REL)],
    "optics": [("optics", (400, 400), 400, 90.0, REL)],  # base perspective, fov 90
    "pannini": [("pannini", (600, 400), 400, _pannini_span(150.0, 1.0, 600, 400), REL)],
    "perspective": [("perspective", (400, 400), 400, 90.0, REL),
                    ("perspective:fov=60", (640, 360), 360, _pinhole(tan(radians(30)) * 360 / 640), REL)],
    "pincushion": [("pincushion", (400, 400), 400, _pinhole(1 / 1.3), REL)],
    "sinusoidal": [("sinusoidal", (800, 400), 400, 180.0, REL)],
    "stereo": [("stereo", (1600, 400), 400, 180.0, REL), ("stereo:tb,base=fisheye,fov=180", (300, 600), 300, 180.0,
                                                          REL)],
    "swirl": [("swirl", (400, 400), 400, _swirl_span(6.0), REL)],
    "tan-fisheye": [("tan-fisheye:fov=120", (400, 400), 400, _tan_fisheye(120.0), REL),
                    # fov 180: t = tan(r F) reaches pi (the back pole, where the image folds) at r = atan(pi) / F
                    ("tan-fisheye", (400, 400), 400 * atan(pi) / (pi / 2), 360.0, REL_CIRCLE)],
    "tetrahedron": [("tetrahedron", (400, 400), 400, degrees(np.arccos(-1 / 3)), REL)],  # (1, -1, 1) to (1, 1, -1)
    "tiled": [("tiled", (400, 400), 200, 90.0, REL), ("tiled:4x1", (1024, 256), 256, 90.0, REL),
              ("tiled:1x4", (256, 1024), 256, 90.0, REL)],
    "tsp": [("tsp", (800, 400), 400, 90.0, REL)],  # the front face, full height
}


def test_every_registered_lens_has_a_case():
    buildable = set()
    for name in REGISTRY:
        try:
            make_lens(name, (400, 400))
        except Exception:  # noqa: BLE001  (a model that needs parameters to exist: lensfun's lens=)
            continue
        buildable.add(name)
    assert buildable - set(CASES) == set(), "say what these lenses' pixels per degree are"
    assert set(CASES) <= set(REGISTRY)


@pytest.mark.parametrize("spec,size,rows,span,tol", [c for cases in CASES.values() for c in cases],
                         ids=[c[0] for cases in CASES.values() for c in cases])
def test_the_default_follows_the_lens_s_own_resolution(spec, size, rows, span, tol):
    lens = make_lens(spec, size)
    expected = rows / span
    assert lens.pixels_per_degree() == pytest.approx(expected, rel=tol)
    rows_180 = 180 * expected
    assert abs(rows_180 - round(rows_180)) < 0.5 - 180 * expected * tol  # the rounding is decided
    assert source_rows(lens) == round(rows_180)


def test_a_tiled_grid_with_an_empty_first_tile_takes_the_first_camera(tmp_path):
    cams = tmp_path / "tiles.toml"
    cams.write_text('[[tiles]]\n\n[[tiles]]\nlens = "fisheye:fov=180,mapping=equisolid"\nyaw = 90\n')
    lens = make_lens(f"tiled:2x1,tiles={cams}", (600, 300))  # tiles of 300 x 300, the second a 180-degree circle
    assert lens.pixels_per_degree() == pytest.approx(300 / 180.0, rel=REL)
