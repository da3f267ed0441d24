"""``tracer render --camera LENS`` without ``--size`` renders the lens's own frame at 512 rows, as ``lenslab warp``
makes an output without a source: a Hammer map 1024 x 512, a Pannini view 768 x 512 (they used to be 512 x 512, a
squashed map); grids and equirect bands keep the sizes they had (square tiles and faces of 256 pixels, square pixels
over an equirect's ranges). A bend or optics over a base model (``swirl:base=equirect``) takes its base's frame.

Each lens's aspect is worked out here, at its default parameters, from its formula's extent (a world map's width and
height at the equator and the pole), its layout (cube faces, halves, eyes side by side) or, for the two projections
that have no top or bottom edge, the frame lenslab documents for them. Widths are whole pixels: the aspect is met to
half a pixel over the 512 rows.
"""

from __future__ import annotations

import math

import numpy as np
import OpenEXR
import pytest

from tracer.cli import build_parser, main

ROWS = 512


def _hammer() -> float:
    """Hammer-Aitoff: x = 2 sqrt2 cos(lat) sin(lon/2) / sqrt(1 + cos(lat) cos(lon/2)), y = sqrt2 sin(lat) / sqrt(...);
    the width at the equator (lon = +-pi) over the height at the poles."""
    def xy(lon, lat):
        z = np.sqrt(1 + np.cos(lat) * np.cos(lon / 2))
        return 2 * np.sqrt(2) * np.cos(lat) * np.sin(lon / 2) / z, np.sqrt(2) * np.sin(lat) / z

    return (xy(np.pi, 0.0)[0] - xy(-np.pi, 0.0)[0]) / (xy(0.0, np.pi / 2)[1] - xy(0.0, -np.pi / 2)[1])


def _mercator() -> float:
    """Mercator at fov 360 and square pixels: x = lon over 2 pi, y = ln tan(pi/4 + lat/2) to the latitude
    atan(sinh(pi)) (85.05 degrees) lenslab's mercator reaches, as web maps do."""
    top = math.atan(math.sinh(math.pi))
    return 2 * math.pi / (2 * math.log(math.tan(math.pi / 4 + top / 2)))


#: width / height of each registered lens's frame at its default parameters, and the spec (the bare name, or an
#: example where the model needs a value)
SQUARE = 1.0  # a fisheye's circle, a view with equal fields across and down, a radial model about the centre
EXPECTED = {
    "ball": SQUARE, "barrel": SQUARE, "brown": SQUARE, "devernay-fov": SQUARE, "distortion": SQUARE,
    "division": SQUARE, "double-sphere": SQUARE, "eucm": SQUARE, "fisheye": SQUARE, "fisheye624": SQUARE,
    "kannala-brandt": SQUARE, "ocam": SQUARE, "omnidir": SQUARE, "opencv": SQUARE,
    "opencv-fisheye": SQUARE, "optics": SQUARE, "perspective": SQUARE, "pincushion": SQUARE, "swirl": SQUARE,
    "tan-fisheye": SQUARE,
    "little-planet": SQUARE, "globe": SQUARE,  # a disc of the sphere
    "octahedron": SQUARE, "tetrahedron": SQUARE,  # the solid unfolded into a square
    "equirect": 360 / 180, "half-equirect": 180 / 180,  # square pixels over its longitudes and latitudes
    "stereo": 2 * 360 / 180,  # two equirect eyes (its default base) side by side
    "cubemap": 3 / 2, "eac": 3 / 2,  # 3 x 2 square faces
    "tiled": 2 / 2,  # 2 x 2 square tiles
    "dual-fisheye": 2 * SQUARE,  # two circles side by side
    "tsp": 2 * SQUARE,  # v360's frame: the front face square, the five others in a square beside it
    "fb-barrel": 4 * 0.5 + 0.5,  # v360's: the caps two squares of half the height in a column, the band 4 such wide
    "fb-barrelsplit": 3 / 2,  # v360's: three columns of two square cells
    "hammer": _hammer(),
    "sinusoidal": (2 * math.pi) / math.pi,  # x = lon cos(lat) at the equator over y = lat
    "cylindrical-equal-area": (2 * math.pi) / 2.0,  # x = lon over y = sin(lat)
    "mercator": _mercator(),
    # no top or bottom edge (central cylinder and Pannini see latitudes to 90 degrees only at infinity): the frames
    # lenslab's models document, 2:1 (latitudes to atan(pi/2) at fov 360) and 3:2 (a photograph's)
    "cylindrical": 2.0, "pannini": 1.5,
    # the calibration sensor's, landscape: lensfun's aspect-ratio of the profile, 1.5 where its XML gives none (as for
    # this Canon EF 8-15mm; tests/lenses/test_lensfun_default_frame.py reads the XML for two lenses)
    "lensfun": 1.5,
}
SPECS = {"lensfun": "lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=10"}


def default_size(spec: str) -> tuple[int, int]:
    """The size ``tracer render --camera spec`` without --size renders (its camera, made as the command makes it)."""
    from tracer.cli import _camera
    from tracer.load import load_scene

    args = build_parser().parse_args(["render", "--scene", "furnace", "--camera", spec, "-o", "x.exr"])
    return _camera(args, load_scene("furnace")).size


def test_every_registered_lens_is_listed():
    from lenslab.lenses import REGISTRY

    assert sorted(EXPECTED) == sorted(REGISTRY)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_the_default_size_has_the_lens_s_aspect(name):
    w, h = default_size(SPECS.get(name, name))
    assert h == ROWS and abs(w / h - EXPECTED[name]) <= 0.5 / h, (w, h)


@pytest.mark.parametrize("spec,base", [("swirl:amount=3,base=equirect", "equirect"),
                                       ("pincushion:k1=0.1,base=cylindrical-equal-area", "cylindrical-equal-area"),
                                       ("brown:k1=0.05,base=sinusoidal", "sinusoidal"),
                                       ("optics:tca=1.001/0.999,base=hammer", "hammer"),
                                       ("distortion:k1=0.1,base=fisheye,fov=180", "fisheye")])
def test_a_lens_over_a_base_takes_the_base_s_frame(tmp_path, spec, base):
    """A bend or optics over a base model draws the base at the same size: its frame is the base's (a swirled
    equirect 2:1, not square), in a render and in a warp's output alike (lenslab warp from an equirect of 512 rows)."""
    w, h = default_size(spec)
    assert h == ROWS and abs(w / h - EXPECTED[base]) <= 0.5 / h, (w, h)
    from lenslab.cli.main import main as lenslab
    from lenslab.io import write

    write(tmp_path / "pano.exr", np.ones((256, 512, 3), np.float32))
    out = tmp_path / "view.exr"
    assert lenslab(["warp", str(tmp_path / "pano.exr"), "--to", spec, "-o", str(out), "-q"]) == 0
    with OpenEXR.File(str(out)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    w, h = int(x1 - x0 + 1), int(y1 - y0 + 1)
    assert abs(w / h - EXPECTED[base]) <= 0.5 / h, (w, h)


@pytest.mark.parametrize("spec,size", [
    # grids: square tiles and faces of 512 rows over 180 degrees, 256 pixels for 90 degrees, in their layout
    ("cubemap", (3 * 256, 2 * 256)), ("cubemap:layout=6x1", (6 * 256, 256)), ("cubemap:layout=1x6", (256, 6 * 256)),
    ("tiled:3x1", (3 * 256, 256)), ("tiled:2x2", (2 * 256, 2 * 256)),
    # equirect ranges: square pixels, 512 rows over 180 degrees
    ("equirect", (512 * 360 // 180, 512)),
    ("equirect:lat_min=-30,lat_max=30", (512 * 360 // 180, round(512 * 60 / 180))),
    ("equirect:lon_min=-90,lon_max=90", (512 * 180 // 180, 512)), ("half-equirect", (512, 512)),
])
def test_grids_and_bands_keep_their_sizes(spec, size):
    assert default_size(spec) == size


@pytest.mark.parametrize("name", ["hammer", "pannini"])
def test_a_render_has_that_size(tmp_path, name):
    """The file itself, read back by OpenEXR's own binding."""
    out = tmp_path / "r.exr"
    assert main(["render", "--scene", "furnace", "--camera", name, "--spp", "1", "-q", "-o", str(out)]) == 0
    with OpenEXR.File(str(out)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    assert (int(x1 - x0 + 1), int(y1 - y0 + 1)) == (round(ROWS * EXPECTED[name]), ROWS)
