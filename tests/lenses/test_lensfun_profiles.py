"""lensfun profiles against lensfun itself (lensfunpy.Modifier, one point per call: its exact scalar path).

lensfun works in float32, so positions agree to about 1e-4 px; 0.01 px is the bound the project
states for lensfun comparisons. The rectilinear image lensfun corrects into is transcribed here in
float64 from lensfun 0.3.4's modifier.cpp: pixel centres at integers, centre ((W-1)/2, (H-1)/2),
``NormScale = 2 / min(W-1, H-1) * coordinate_correction`` and the focal length in those units,
``focal / NormalizedInMillimeters``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

lf = pytest.importorskip("lensfunpy")

from lenslab.lenses import make_lens  # noqa: E402
from lenslab.lenses.lensfun import database as lensfun_db  # noqa: E402

POS_TOL = 0.01  # px: lensfun computes in float32 (~1e-4 px at these sizes); the project's lensfun bound
VIG_TOL = 1e-5  # relative: float32 illumination with lensfun's running r^2 update across a row

# (lens, crop or camera, focal, aperture, distance, size, real focal over nominal when the XML has one)
CASES = {
    "ptlens, linear TCA, vignetting, other crop": ("Nikon AF-S DX Nikkor 35mm f/1.8G", "crop=1.5", 35, 2.8, 5, (600, 400)),
    "poly3, poly3 TCA, vignetting, zoom between calibrations": (
        "Canon EF 70-300mm f/4.5-5.6 DO IS USM", "crop=1", 120, 6.3, 10, (600, 400)),
    "poly5, portrait": ("Canon PowerShot G12 & compatibles (Standard)", "", 10, 0, 1000, (300, 450)),
    "fisheye (equidistant), ptlens": ("Sigma 10mm f/2.8 EX DC Fisheye HSM", "crop=1.5", 10, 0, 1000, (600, 400)),
    "equisolid, between calibrations": ("Canon EF 8-15mm f/4L Fisheye USM", "crop=1", 10, 0, 1000, (600, 400)),
    "stereographic": ("Samyang 12mm f/2.8 Fish-Eye ED AS NCS", "crop=1", 12, 0, 1000, (600, 400)),
    "equisolid with a real focal length and 4:3 sensor": ("AEE SD19 & compatibles", "", 5, 0, 1000, (640, 480)),
    "stereographic on a named camera": ("Samyang 8mm f/3.5 Fish-Eye CS", "camera=Canon EOS 600D", 8, 0, 1000, (600, 400)),
}

# the focal length lensfun's geometry step uses, mm: nominal, or the XML's real focal length over
# Hugin's correction 1 - a - b - c (values read off actioncams.xml of lensfun 0.3.4)
REAL_FOCAL = {"AEE SD19 & compatibles": 2.61 / (1 - 0.05109 + 0.12092 - 0.10955)}
# aspect ratio of the calibration sensor from the XML (lensfun's default 3:2 otherwise)
ASPECT = {"AEE SD19 & compatibles": 4 / 3, "Canon PowerShot G12 & compatibles (Standard)": 4 / 3}


def setup(case):
    name, extra, focal, aperture, distance, size = CASES[case]
    spec = f'lensfun:lens="{name}",focal={focal},distance={distance}' + (f",aperture={aperture}" if aperture else "")
    spec += f",{extra}" if extra else ""
    lens = make_lens(spec, size)
    lfl = lensfun_db.pick_lens(name)
    assert lfl.model == name
    if extra.startswith("camera="):  # the camera's crop factor, as lensfun's database gives it
        cam = [c for c in lensfun_db.database().cameras if c.model == extra.split("=")[1]]
        assert len(cam) == 1
        crop = float(cam[0].crop_factor)
        assert crop != float(lfl.crop_factor)  # the calibration's sensor differs: the rescaling is exercised
    else:
        crop = float(extra.split("=")[1]) if extra else float(lfl.crop_factor)
    return lens, lfl, crop, focal, aperture or 0.0, distance, size


def rect_frame(lfl, crop, focal, name, size):
    """lensfun's rectilinear target: pixel centre (integers) <-> plane (x right, y down), focal."""
    w, h = max(size[0] - 1, 1), max(size[1] - 1, 1)
    s = min(w, h)
    arc = math.sqrt(ASPECT.get(name, 1.5) ** 2 + 1)
    cc = 1 / math.sqrt((max(w, h) / s) ** 2 + 1) * float(lfl.crop_factor) / crop * arc
    ns = 2 / s * cc
    nim = math.hypot(36, 24) / 2 / arc / float(lfl.crop_factor)
    f = REAL_FOCAL.get(name, focal) / nim
    return np.array([w / 2, h / 2]), ns, f, arc


def grid(size, n=6):
    xs = np.linspace(0, size[0] - 1, n).round()
    ys = np.linspace(0, size[1] - 1, n).round()
    return [(float(x), float(y)) for y in ys for x in xs]


def modifier(lfl, crop, size, focal, aperture, distance, flags, reverse, **kw):
    m = lf.Modifier(lfl, crop, size[0], size[1])
    m.initialize(focal, aperture or 5.6, distance, scale=1.0, targeom=lf.LensType.RECTILINEAR,
                 flags=flags, reverse=reverse, **kw)
    return m


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("reverse", [False, True], ids=["remove", "apply"])
def test_geometry_matches_lensfun(case, reverse):
    lens, lfl, crop, focal, aperture, distance, size = setup(case)
    centre, ns, f, _ = rect_frame(lfl, crop, focal, lfl.model, size)
    flags = lf.ModifyFlags.DISTORTION | lf.ModifyFlags.GEOMETRY
    m = modifier(lfl, crop, size, focal, aperture, distance, flags, reverse)
    compared = 0
    for (i, j) in grid(size):
        ref = m.apply_geometry_distortion(i, j, 1, 1)[0, 0].astype(np.float64)
        if not reverse:  # rectilinear pixel -> its ray -> our photo position
            q = (np.array([i, j]) - centre) * ns
            d = np.array([q[0], -q[1], f])
            xy, ok = lens.dir_to_pixel_unbounded(d[None])
            got = xy[0] - 0.5
        else:  # photo pixel -> our ray -> the rectilinear position
            d, ok = lens.pixel_to_dir(np.array([[i + 0.5, j + 0.5]]))
            ok &= d[:, 2] > 0.05  # rays near 90 degrees have no useful rectilinear position
            got = centre + np.array([d[0, 0], -d[0, 1]]) * f / max(d[0, 2], 0.05) / ns
        if not ok[0] or not np.isfinite(ref).all() or np.abs(ref).max() > 1e5:
            continue
        compared += 1
        assert np.abs(got - ref).max() < POS_TOL, (case, (i, j), got, ref)
    # at least half the 36 points take part (a fisheye's corners lie beyond the rectilinear plane)
    assert compared >= 18


TCA_CASES = ["ptlens, linear TCA, vignetting, other crop", "poly3, poly3 TCA, vignetting, zoom between calibrations"]


@pytest.mark.parametrize("case", TCA_CASES)
@pytest.mark.parametrize("reverse", [False, True], ids=["remove", "apply"])
def test_tca_matches_lensfun(case, reverse):
    lens, lfl, crop, focal, aperture, distance, size = setup(case)
    red, green, blue = lens.channel_lenses()
    assert green is lens
    m = modifier(lfl, crop, size, focal, aperture, distance, lf.ModifyFlags.TCA, reverse)
    for (i, j) in grid(size):
        ref = m.apply_subpixel_distortion(i, j, 1, 1)[0, 0].astype(np.float64) + 0.5  # (R, G, B) x (x, y)
        x = np.array([[i + 0.5, j + 0.5]])
        assert np.abs(ref[1] - x[0]).max() < 1e-3  # green stays (float32 round trip of the pixel position)
        for c, ch in ((0, red), (2, blue)):
            if not reverse:  # corrected (green) position -> where channel c's picture lies
                d, _ = green.pixel_to_dir(x)
                got, ok = ch.dir_to_pixel_unbounded(d)
            else:  # channel c's picture at x -> where the corrected image has it
                d, _ = ch.pixel_to_dir(x)
                got, ok = green.dir_to_pixel_unbounded(d)
            assert ok[0]
            assert np.abs(got[0] - ref[c]).max() < POS_TOL, (case, c, (i, j), got, ref[c])


@pytest.mark.parametrize("case", TCA_CASES)
@pytest.mark.parametrize("reverse", [False, True], ids=["remove", "apply"])
def test_vignetting_matches_lensfun(case, reverse):
    lens, lfl, crop, focal, aperture, distance, size = setup(case)
    m = modifier(lfl, crop, size, focal, aperture, distance, lf.ModifyFlags.VIGNETTING, reverse,
                 pixel_format=np.float32)
    img = np.ones((size[1], size[0], 3), np.float32)
    assert m.apply_color_modification(img)
    yy, xx = np.mgrid[0 : size[1], 0 : size[0]]
    fall = lens.falloff(np.stack([xx + 0.5, yy + 0.5], -1))
    want = fall if reverse else 1.0 / fall  # applying multiplies by the illumination, removing divides
    assert fall.min() < 0.95  # a real falloff is being compared
    np.testing.assert_allclose(img[..., 1], want, rtol=VIG_TOL)


def test_effects_choose_and_quotes_keep_commas():
    name = "Canon DIGITAL IXUS 400 & compatibles, with Tiffen MegaPlus 0.56 converter"
    lens = make_lens(f'lensfun:lens="{name}"', (64, 48))
    assert lens.profile.model == name
    assert make_lens(lens.spec(), (64, 48)) == lens
    only = make_lens('lensfun:lens="Canon EF 70-300mm f/4.5-5.6 DO IS USM",effects=tca+vignetting', (64, 48))
    assert only.dist is None and only.channel_lenses() is not None and only.falloff([[0.0, 0.0]]) is not None
    none = make_lens('lensfun:lens="Canon EF 70-300mm f/4.5-5.6 DO IS USM",effects=none', (64, 48))
    assert none.channel_lenses() is None and none.falloff([[0.0, 0.0]]) is None


def test_lenses_command_shows_what_profiles_hold(capsys):
    from lenslab.cli.main import main

    assert main(["lenses", "--lensfun", "samyang 8mm"]) == 0
    out = capsys.readouterr().out
    # the bundled database's entry (lensfun 0.3.4 slr-samyang.xml): stereographic, ptlens and poly3 TCA at 8 mm
    assert "Samyang 8mm f/3.5 Fish-Eye CS" in out
    block = out.split("Samyang 8mm f/3.5 Fish-Eye CS", 1)[1].split("\n\n", 1)[0]
    assert "stereographic" in block and "ptlens at 8 mm" in block and "poly3 at 8 mm" in block
    assert main(["lenses", "--lensfun", "no such lens anywhere"]) != 0


def test_own_database_with_or_without_the_bundled_one(tmp_path, capsys):
    from lenslab.cli.main import main

    (tmp_path / "mine.xml").write_text(
        '<lensdatabase version="1"><lens><maker>Acme</maker><model>Acme Test 20mm f/2</model>'
        "<mount>Canon EF</mount><cropfactor>1</cropfactor><calibration>"
        '<distortion model="poly3" focal="20" k1="0.01"/></calibration></lens></lensdatabase>')
    assert main(["lenses", "--lensfun", "acme test", "--lensfun-db", str(tmp_path), "--lensfun-db-only"]) == 0
    assert "poly3 at 20 mm" in capsys.readouterr().out
    assert lensfun_db.find_lenses("samyang 8mm") and not lensfun_db.find_lenses("acme test")  # for that search only
    with lensfun_db.using_database([str(tmp_path)], bundled=False):
        assert not lensfun_db.find_lenses("samyang 8mm")  # the bundled files are left out
        lens = make_lens("lensfun:lens=acme test", (300, 200))
    # poly3 on lensfun's plane: a point at r_u lands at r_u P(r_u), P = 1 - k1 + k1 r_u^2 (k1 = 0.01)
    arc = math.hypot(1.5, 1)  # lensfun's default 3:2 calibration sensor, image 299 x 199 between centres
    ns = 2 / 199 * arc / math.hypot(299 / 199, 1)
    q = np.array([100 - 149.5, 50 - 99.5]) * ns  # an undistorted point
    got, ok = lens.dir_to_pixel(np.array([[q[0], -q[1], lens.f]]))
    want = q * (0.99 + 0.01 * (q @ q)) / ns + np.array([150.0, 100.0])
    # 1e-7 px: lensfun stores k1 = 0.01 as float32 (off by 2e-10), which moves this point by ~6e-9 px
    assert ok[0] and np.abs(got[0] - want).max() < 1e-7
    with lensfun_db.using_database([str(tmp_path)], bundled=True):
        assert lensfun_db.find_lenses("samyang 8mm") and lensfun_db.find_lenses("acme test")


@pytest.mark.parametrize("reverse", [False, True], ids=["remove", "apply"])
def test_warp_removes_and_applies_vignetting_as_lensfun_does(reverse):
    """A flat white frame warped between the lens with its vignetting and without (same geometry, same
    pixels): lensfun's own colour modification of the same frame is the answer."""
    from lenslab.lenses import Camera, Pose
    from lenslab.warp import warp

    case = "poly3, poly3 TCA, vignetting, zoom between calibrations"
    lens, lfl, crop, focal, aperture, distance, size = setup(case)
    assert "effects" not in lens.spec()  # all of them: the two below choose
    vig = make_lens(f"{lens.spec()},effects=vignetting", size)
    bare = make_lens(f"{lens.spec()},effects=none", size)
    src, dst = (bare, vig) if reverse else (vig, bare)
    ones = np.ones((size[1], size[0], 3), np.float32)
    pose = Pose.from_ypr(0, 0, 0)
    out, alpha = warp(ones, Camera(src, pose), Camera(dst, pose), filter="bilinear", samples=1)
    m = modifier(lfl, crop, size, focal, aperture, distance, lf.ModifyFlags.VIGNETTING, reverse,
                 pixel_format=np.float32)
    want = np.ones_like(ones)
    assert m.apply_color_modification(want)
    assert (alpha == 1).all()
    # 2e-5 relative: lensfun's float32 illumination (1e-5, see VIG_TOL) and the warp's float32 output
    np.testing.assert_allclose(out, want, rtol=2e-5)


OFFSET_XML = """<lensdatabase version="1">
<lens><maker>Acme</maker><model>Acme Offset 24mm f/2</model><mount>Canon EF</mount><cropfactor>1.5</cropfactor>
<aspect-ratio>4:3</aspect-ratio><center x="0.06" y="-0.04"/>
<calibration><distortion model="ptlens" focal="24" a="0.01" b="-0.03" c="0.02"/>
<tca model="linear" focal="24" kr="1.0004" kb="0.9997"/>
<vignetting model="pa" focal="24" aperture="2" distance="10" k1="-0.4" k2="0.2" k3="-0.05"/></calibration></lens>
</lensdatabase>"""


def test_own_profile_with_an_off_centre_lens_and_another_sensor(tmp_path):
    """A profile of your own (no lens in the bundled database has a centre offset): 4:3 calibration
    sensor at crop 1.5, image at crop 1.6, lens centre moved; geometry, TCA and vignetting against lensfun."""
    (tmp_path / "acme.xml").write_text(OFFSET_XML)
    with lensfun_db.using_database([str(tmp_path)], bundled=False):
        size = (500, 360)
        lens = make_lens("lensfun:lens=acme offset,crop=1.6,aperture=2,distance=10", size)
        lfl = lensfun_db.pick_lens("acme offset")
        # lensfun's frame, transcribed: unit radius over the 4:3 calibration sensor, centre moved by
        # (0.06, -0.04) units of half the shorter span
        s = 359
        ns = 2 / s * (math.hypot(4 / 3, 1) / math.hypot(499 / 359, 1) * 1.5 / 1.6)
        centre = np.array([499 / 2 + 0.06 * s / 2, 359 / 2 - 0.04 * s / 2])
        f = 24 / (math.hypot(36, 24) / 2 / math.hypot(4 / 3, 1) / 1.5)
        m = lf.Modifier(lfl, 1.6, *size)
        m.initialize(24, 2, 10, scale=1.0, flags=lf.ModifyFlags.DISTORTION)
        for (i, j) in grid(size):
            ref = m.apply_geometry_distortion(i, j, 1, 1)[0, 0].astype(np.float64)
            q = (np.array([i, j]) - centre) * ns
            xy, ok = lens.dir_to_pixel_unbounded(np.array([[q[0], -q[1], f]]))
            assert ok[0] and np.abs(xy[0] - 0.5 - ref).max() < POS_TOL, ((i, j), xy, ref)
        m = lf.Modifier(lfl, 1.6, *size)
        m.initialize(24, 2, 10, scale=1.0, flags=lf.ModifyFlags.TCA)
        red, green, blue = lens.channel_lenses()
        for (i, j) in grid(size):
            ref = m.apply_subpixel_distortion(i, j, 1, 1)[0, 0].astype(np.float64) + 0.5
            d, _ = green.pixel_to_dir(np.array([[i + 0.5, j + 0.5]]))
            for c, ch in ((0, red), (2, blue)):
                got, ok = ch.dir_to_pixel_unbounded(d)
                assert ok[0] and np.abs(got[0] - ref[c]).max() < POS_TOL
        m = lf.Modifier(lfl, 1.6, *size)
        m.initialize(24, 2, 10, scale=1.0, flags=lf.ModifyFlags.VIGNETTING, pixel_format=np.float32)
        img = np.ones((size[1], size[0], 3), np.float32)
        assert m.apply_color_modification(img)
        yy, xx = np.mgrid[0 : size[1], 0 : size[0]]
        np.testing.assert_allclose(img[..., 1], 1 / lens.falloff(np.stack([xx + 0.5, yy + 0.5], -1)), rtol=VIG_TOL)


TYPE_XML = """<lensdatabase version="1">
<lens><maker>Acme</maker><model>Acme Projection 20mm f/2</model><mount>Canon EF</mount><cropfactor>1</cropfactor>
<type>{kind}</type><calibration><distortion model="poly3" focal="20" k1="0.01"/></calibration></lens>
</lensdatabase>"""


@pytest.mark.parametrize("kind", ["fisheye_thoby", "orthographic", "equirectangular", "panoramic"])
@pytest.mark.parametrize("reverse", [False, True], ids=["remove", "apply"])
def test_every_projection_type_against_lensfun(kind, reverse, tmp_path):
    """The projection types no lens of the bundled database tests (or only one does), in a profile of
    your own, through lensfun's geometry conversion to rectilinear."""
    (tmp_path / "p.xml").write_text(TYPE_XML.format(kind=kind))
    with lensfun_db.using_database([str(tmp_path)], bundled=False):
        size = (600, 400)
        lens = make_lens("lensfun:lens=acme projection,focal=20", size)
        lfl = lensfun_db.pick_lens("acme projection")
        assert lens.profile.type == {"fisheye_thoby": "thoby"}.get(kind, kind)
        # no real focal length in the profile: lensfun's geometry uses the nominal one (its Hugin
        # correction is applied and undone)
        centre, ns, f, _ = rect_frame(lfl, 1.0, 20, "", size)
        flags = lf.ModifyFlags.DISTORTION | lf.ModifyFlags.GEOMETRY
        m = modifier(lfl, 1.0, size, 20, 0, 1000, flags, reverse)
        compared = 0
        for (i, j) in grid(size):
            ref = m.apply_geometry_distortion(i, j, 1, 1)[0, 0].astype(np.float64)
            if not reverse:
                q = (np.array([i, j]) - centre) * ns
                xy, ok = lens.dir_to_pixel_unbounded(np.array([[q[0], -q[1], f]]))
                got = xy[0] - 0.5
            else:
                d, ok = lens.pixel_to_dir(np.array([[i + 0.5, j + 0.5]]))
                ok &= d[:, 2] > 0.05
                got = centre + np.array([d[0, 0], -d[0, 1]]) * f / max(d[0, 2], 0.05) / ns
            # positions beyond a frame's width outside the image are left out: there lensfun's float32
            # trigonometry is off by more than 0.01 px (0.012 px at 2000 px out, a Thoby corner)
            if not ok[0] or not np.isfinite(ref).all() or np.abs(ref - centre).max() > 1.5 * size[0]:
                continue
            compared += 1
            assert np.abs(got - ref).max() < POS_TOL, (kind, (i, j), got, ref)
        assert compared >= 18, compared  # at least half the points
