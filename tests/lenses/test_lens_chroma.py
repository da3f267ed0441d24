"""Chromatic aberration and vignetting: per-channel lenses and falloff, for optics: and lensfun: lenses,
and the tracer's ray per channel and falloff weight."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from lenslab.lenses import Camera, make_lens

W, H = 240, 160


def perspective_dir(xy, width, height, fov):
    """lenslab's pinhole, transcribed: u = 2x/W - 1, v = (1 - 2y/H) H/W, d ~ (u t, v t, 1)."""
    t = math.tan(math.radians(fov) / 2)
    u = 2 * xy[..., 0] / width - 1
    v = (1 - 2 * xy[..., 1] / height) * height / width
    d = np.stack([u * t, v * t, np.ones_like(u)], -1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def dot_centroids(lens, d0, radius, box, ss=16):
    """Render a white dot (directions within ``radius`` rad of ``d0``) on black through each channel
    lens, ``ss x ss`` samples per pixel over ``box`` = (x0, y0, x1, y1); return the (3, 2) centroids."""
    x0, y0, x1, y1 = box
    off = (np.arange(ss) + 0.5) / ss
    xs = (np.arange(x0, x1)[:, None] + off[None]).ravel()
    ys = (np.arange(y0, y1)[:, None] + off[None]).ravel()
    xy = np.stack(np.meshgrid(xs, ys), -1)
    out = []
    for ch in lens.channel_lenses():
        d, ok = ch.pixel_to_dir(xy)
        lit = ok & (d @ d0 > math.cos(radius))
        out.append(xy[lit].mean(axis=0))
    return np.array(out)


def test_white_dot_moves_by_the_optics_tca():
    # red 1.2 % out and blue 0.8 % in at r = 1, plus a cubic term for red
    lens = make_lens("optics:tca=1.01/0.992/0/0/0.002/0,base=perspective,fov=70", (W, H))
    xy_g = np.array([200.0, 40.0])  # the dot's green picture, near a corner
    d0 = perspective_dir(xy_g, W, H, 70)
    cent = dot_centroids(lens, d0, math.radians(0.4), (185, 25, 220, 57))
    centre, half = np.array([W / 2, H / 2]), min(W, H) / 2
    g = cent[1]
    r = np.linalg.norm(g - centre) / half
    want_red = centre + (g - centre) * (1.01 + 0.002 * r * r)  # lensfun's poly3: r (v + c r + b r^2)
    want_blue = centre + (g - centre) * 0.992
    # 0.01 px: the dot's picture is scaled by at most 1.3 % across its 2.4 px radius, so its centroid
    # sits within ~1e-3 px of the scaled centre; 16 x 16 samples per pixel add ~1e-3 px
    assert np.abs(cent[0] - want_red).max() < 0.01
    assert np.abs(cent[2] - want_blue).max() < 0.01
    assert np.linalg.norm(cent[0] - g) > 1.0  # a shift of well over a pixel is measured


def test_white_dot_moves_by_a_real_lens_tca():
    lf = pytest.importorskip("lensfunpy")
    from lenslab.lenses.lensfun import database as lensfun_db

    name, size = "Canon EF 70-300mm f/4.5-5.6 DO IS USM", (600, 400)
    lens = make_lens(f"lensfun:lens={name},focal=120,effects=tca", size)
    t = lensfun_db.pick_lens(name).interpolate_tca(120.0)
    assert t.model == lf.TCAModel.POLY3
    vr, vb, cr, cb, br, bb = t.terms
    # lensfun's normalisation (modifier.cpp, 3:2 calibration on a 3:2 image): centre at ((W-1)/2, (H-1)/2)
    # in pixel-centre coordinates, unit min(W-1, H-1) / 2
    centre = np.array([299.5, 199.5]) + 0.5
    half = 399 / 2 * math.hypot(599 / 399, 1) / math.hypot(1.5, 1)
    xy_g = np.array([560.0, 40.0])
    d, _ = lens.pixel_to_dir(xy_g[None])
    cent = dot_centroids(lens, d[0], math.radians(0.1), (548, 28, 573, 53), ss=24)
    g = cent[1]
    r = np.linalg.norm(g - centre) / half
    want_red = centre + (g - centre) * (vr + cr * r + br * r * r)
    want_blue = centre + (g - centre) * (vb + cb * r + bb * r * r)
    # 0.003 px against shifts of 0.01 px (red) and 0.3 px (blue) here: the dot (3.4 px radius) is scaled
    # by at most 1e-3, and 24 x 24 samples per pixel place a centroid to ~1e-3 px
    assert np.abs(cent[0] - want_red).max() < 3e-3
    assert np.abs(cent[2] - want_blue).max() < 3e-3
    assert np.linalg.norm(cent[2] - g) > 0.2  # the blue shift is measured, not assumed


def test_optics_falloff_pa_and_cos4():
    xy = np.array([[0.0, 0.0], [120.0, 80.0], [30.5, 140.25]])
    pa = make_lens("optics:vignetting=pa/-0.3/0.1/-0.05,base=perspective,fov=70", (W, H))
    r = np.hypot(xy[:, 0] - W / 2, xy[:, 1] - H / 2) / (math.hypot(W, H) / 2)  # r = 1 at the corner
    np.testing.assert_allclose(pa.falloff(xy), 1 - 0.3 * r**2 + 0.1 * r**4 - 0.05 * r**6, rtol=1e-14)
    c4 = make_lens("optics:vignetting=cos4,base=perspective,fov=70", (W, H))
    cos = perspective_dir(xy, W, H, 70)[:, 2]
    np.testing.assert_allclose(c4.falloff(xy), cos**4, rtol=1e-14)
    assert make_lens("optics:base=perspective", (W, H)).falloff(xy) is None


def test_tracer_traces_a_ray_per_channel_and_the_falloff():
    import tracer
    from tracer.envlight import EquirectEnvironment
    from tracer.scene import merge_meshes

    ew, eh = 720, 360
    lon = (np.arange(ew) + 0.5) / ew * 2 * np.pi
    lat = (np.arange(eh) + 0.5) / eh * np.pi
    env_img = np.stack([
        1 + 0.5 * np.sin(3 * lon)[None, :] * np.sin(lat)[:, None],
        1 + 0.5 * np.cos(2 * lon)[None, :] * np.ones_like(lat)[:, None],
        1 + 0.5 * np.cos(4 * lat)[:, None] * np.ones_like(lon)[None, :],
    ], -1).astype(np.float32)
    env = EquirectEnvironment(env_img)
    scene = merge_meshes([], environment=env)
    spec = "optics:tca=1.03/0.97,vignetting=pa/-0.3/0.1/-0.05,base=perspective,fov=70"
    cam = Camera.from_spec(spec, (W, H))
    res = tracer.render(scene, cam, spp=1, seed=None, integrator="direct")
    yy, xx = np.mgrid[0:H, 0:W]
    xy = np.stack([xx + 0.5, yy + 0.5], -1).astype(np.float64)
    centre, half = np.array([W / 2, H / 2]), min(W, H) / 2
    r = np.hypot(xy[..., 0] - W / 2, xy[..., 1] - H / 2) / (math.hypot(W, H) / 2)
    fall = 1 - 0.3 * r**2 + 0.1 * r**4 - 0.05 * r**6
    for c, k in ((0, 1.03), (1, 1.0), (2, 0.97)):
        xy_g = centre + (xy - centre) / k  # the green picture of what channel c shows at xy
        want = env.eval(perspective_dir(xy_g, W, H, 70).reshape(-1, 3))[:, c].reshape(H, W) * fall
        got = res.image[..., c]
        # the environment is looked up per pixel of the panorama: a ray on a panorama pixel's edge may
        # round to its neighbour, off by at most one step of the smooth panorama (< 0.02); all others agree
        # to float32
        diff = np.abs(got - want)
        assert (diff > 1e-5 * np.abs(want).max()).mean() < 0.01
        assert diff.max() < 0.02
    assert np.abs(res.image[..., 0] - res.image[..., 2]).max() > 0.05  # red and blue really differ


@settings(max_examples=60, deadline=None)
@given(st.floats(0.9, 1.1), st.floats(-0.05, 0.05), st.floats(-0.05, 0.05), st.floats(0.0, 1.5))
@example(1.0, 0.04614617655754827, -0.03125, 1.5)  # the fold, r_d computed a few ulps above f(r_max)
@example(1.0, 0.0, -0.03125, 1.5)  # the fold: r fixed only to ~1e-8 there
def test_radial_inverse_solves_lensfun_polynomials(v, c, b, frac):
    """r P(r) at the solved radius gives back r_d (float64 transcription of lensfun's poly3 TCA)."""
    from lenslab.lenses.formulas.radial import Radial

    rad = Radial((v, c, b))
    r_top = min(rad.r_max, 8.0)
    ru = np.array([frac / 1.5 * r_top])
    rd = ru * (v + c * ru + b * ru * ru)
    got, ok = rad.inverse(rd)
    assert ok[0]  # frac = 1.5 is the fold itself (f' = 0 at r_max): still on the branch
    # backward error: the solved radius gives r_d back to 1e-13 (the polynomial's own rounding is ~1e-16 r_d)
    back = got[0] * (v + c * got[0] + b * got[0] ** 2)
    assert abs(back - rd[0]) <= 1e-13 * max(1.0, rd[0])
    # forward error: the backward error divided by the slope f'(r); the solve stops at 1e-14 relative steps.
    # At the fold the slope is 0 and the radius is fixed only to sqrt(rounding of r_d) ~ 1e-8 (not tested)
    slope = v + 2 * c * ru[0] + 3 * b * ru[0] ** 2
    if slope > 1e-3:
        assert abs(got[0] - ru[0]) <= 1e-12 * max(1.0, ru[0]) / slope + 1e-12


CORNELL_EYE = (0.278, 0.274, 0.001)  # as in test_validate_cornell: the box's open front, looking in
#: (lens with effects, the same geometry without them)
EFFECT_SPECS = [
    ("optics:tca=1.01/0.99,vignetting=pa/-0.3/0.1/-0.05,base=perspective,fov=90", "perspective:fov=90"),
    ("lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=12,aperture=4",  # distortion, TCA, vignetting
     "lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=12,effects=distortion"),
]


@pytest.mark.slow
@pytest.mark.parametrize("spec,plain_spec", EFFECT_SPECS, ids=[s for s, _ in EFFECT_SPECS])
def test_a_warp_per_channel_with_falloff_agrees_with_a_direct_trace(spec, plain_spec):
    """The Cornell box traced into a panorama, warped into each channel lens and multiplied by the
    falloff, against the tracer's own render through the lens (a ray per channel, falloff weights)."""
    pytest.importorskip("lensfunpy")
    from lenslab import metrics
    from lenslab.validate.run import WarpSetting, call_warp, check, edges_for, panorama_camera
    from lenslab.warp import warp
    from tracer.validate.source import make_source

    source = make_source("cornell", noise_free=True)  # point light, direct integrator, fixed samples
    target = Camera.from_spec(spec, (128, 128), eye=CORNELL_EYE, yaw=10.0, pitch=-5.0)
    pcam = panorama_camera(target, (1024, 512))
    pano = source.render(pcam, spp=1, seed=None)
    ref = source.render(target, spp=16, seed=None)
    edges, _ = edges_for(ref, 2, shadows=False)
    setting = WarpSetting.parse("antialias")
    plain = make_lens(plain_spec, (128, 128))  # green's geometry, with no effects for the engine to apply
    red, _, blue = target.lens.channel_lenses()
    img = np.zeros((128, 128, 3), np.float32)
    for c, ch in enumerate((red, plain, blue)):
        out, a = call_warp(warp, pano.image, pcam, Camera(ch, target.pose), setting)
        img[..., c] = out[..., c]
        if c == 1:
            alpha = a  # alpha is the green (geometric) lens's
    yy, xx = np.mgrid[0:128, 0:128]
    img *= target.lens.falloff(np.stack([xx + 0.5, yy + 0.5], -1))[..., None].astype(np.float32)
    m = metrics.compare(ref.image, img, ref.alpha, alpha, edges=edges, ref_stderr=ref.stderr, with_flip=False)
    # the validation bounds every lens model meets (1% away from edges, 2% overall; see test_validate_cornell)
    verdict = check(m, interior=0.01, overall=0.02)
    assert verdict, f"{spec}: {verdict}"
    # the engine's own warp through the lens (channel lenses and falloff asked of the lens) does the same
    whole, a = call_warp(warp, pano.image, pcam, target, setting)
    np.testing.assert_array_equal(a, alpha)
    m2 = metrics.compare(ref.image, whole, ref.alpha, a, edges=edges, ref_stderr=ref.stderr, with_flip=False)
    assert check(m2, interior=0.01, overall=0.02), spec
    # and agrees with the composite (measured: identical, or 1e-10 relative): 1e-6 of the mean allows the
    # float32 rounding of multiplying by the falloff in another order
    assert np.abs(whole - img).mean() <= 1e-6 * np.abs(img).mean()
    # the plain geometric warp (one ray for all channels, no falloff) does not: the effects are traced
    geo, a = call_warp(warp, pano.image, pcam, Camera(plain, target.pose), setting)
    bad = metrics.compare(ref.image, geo, ref.alpha, a, edges=edges, ref_stderr=ref.stderr, with_flip=False)
    assert not check(bad, interior=0.01, overall=0.02)


def test_white_dot_warped_through_a_real_lens_moves_by_its_tca():
    """A soft white dot on black, warped by the engine into a lens with the profile's TCA: the red and
    blue centroids sit where lensfun's poly3 terms (lensfunpy's interpolation at 120 mm) put them."""
    pytest.importorskip("lensfunpy")
    from lenslab.lenses import Pose
    from lenslab.lenses.lensfun import database as lensfun_db
    from lenslab.warp import warp

    name = "Canon EF 70-300mm f/4.5-5.6 DO IS USM"
    dst = make_lens(f"lensfun:lens={name},focal=120,effects=tca", (600, 400))
    src = make_lens(f"lensfun:lens={name},focal=120,effects=none", (1200, 800))  # same projection, no TCA
    d0, _ = dst.pixel_to_dir(np.array([[560.0, 40.0]]))
    p0, _ = src.dir_to_pixel(d0)
    yy, xx = np.mgrid[0:800, 0:1200]
    dot = np.exp(-((xx + 0.5 - p0[0, 0]) ** 2 + (yy + 0.5 - p0[0, 1]) ** 2) / (2 * 4.0**2)).astype(np.float32)
    pose = Pose.from_ypr(0, 0, 0)
    out, _ = warp(np.repeat(dot[..., None], 3, -1), Camera(src, pose), Camera(dst, pose), filter="bicubic", samples=4)
    ys, xs = np.mgrid[20:60, 540:580]
    win = out[20:60, 540:580]
    cent = np.array([[(win[..., c] * (xs + 0.5)).sum() / win[..., c].sum(),
                      (win[..., c] * (ys + 0.5)).sum() / win[..., c].sum()] for c in range(3)])
    vr, vb, cr, cb, br, bb = lensfun_db.pick_lens(name).interpolate_tca(120.0).terms
    centre = np.array([300.0, 200.0])  # ((W-1)/2, (H-1)/2) + 0.5: lensfun's centre in lenslab's pixels
    half = 399 / 2 * math.hypot(599 / 399, 1) / math.hypot(1.5, 1)  # lensfun's unit radius, px
    g = cent[1]
    r = np.linalg.norm(g - centre) / half
    # 1e-3 px (measured 8e-5): the dot is scaled by at most 1e-3 across its width and resampled bicubically
    np.testing.assert_allclose(cent[0], centre + (g - centre) * (vr + cr * r + br * r * r), atol=1e-3)
    np.testing.assert_allclose(cent[2], centre + (g - centre) * (vb + cb * r + bb * r * r), atol=1e-3)
    assert np.linalg.norm(cent[2] - g) > 0.2  # blue moves by 0.29 px here: measured, not assumed
