"""The alpha contract (docs/conventions.md): coverage stays in [0, 1] after every lens and effect,
vignetting changes light and never coverage, an identity lens changes nothing, a finite source stays
finite, and the straight colour a compositor recovers is the colour the warp meant."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.io.alpha import settle
from lenslab.lenses import Camera
from lenslab.lenses.protocol import MIN_FALLOFF
from lenslab.warp.optics import falloff_image
from lenslab.warp import warp
from tests.lenses.test_lenses_roundtrip import CASES

W = 96
#: one case per registered lens name (the round-trip table covers them all), made small
ONE_PER_LENS = list({spec.partition(":")[0]: (spec, size) for spec, size in reversed(CASES)}.values())
# and every lensfun profile and optics case of that table (their TCA and vignetting are effects of their own)
ONE_PER_LENS += [c for c in CASES if c[0].startswith(("lensfun", "optics")) and c not in ONE_PER_LENS]
EFFECTS = [("bilinear", False), ("nearest", False), ("bicubic", False), ("lanczos", False), ("bilinear", True)]


def small(spec, size):
    w, h = size
    return W, max(2, round(h * W / w)) if h <= 4 * w else 2 * W


def rgba_pano(w, h, seed=0):
    """Premultiplied RGBA: straight colour in [0, 1], alpha hard-edged blocks of 0, 1 and 0.4 (sharp edges
    make bicubic and lanczos ring in alpha as well as colour)."""
    rng = np.random.default_rng(seed)
    straight = rng.random((h, w, 3)).astype(np.float32)
    a = np.where((np.arange(w)[None, :] // 7 + np.arange(h)[:, None] // 5) % 3 == 0, 0.0, 1.0)
    a[(np.arange(h) // 5) % 4 == 1] = 0.4
    a = a.astype(np.float32)[..., None]
    return np.concatenate([straight * a, a], -1)


def assert_contract(out, coverage):
    assert np.isfinite(out).all() and np.isfinite(coverage).all()
    assert coverage.min() >= 0.0 and coverage.max() <= 1.0
    a = out[..., -1]
    assert a.min() >= 0.0 and a.max() <= 1.0


@pytest.mark.parametrize("spec,size", ONE_PER_LENS, ids=[c[0] for c in ONE_PER_LENS])
@pytest.mark.parametrize("filt,aa", EFFECTS, ids=[f"{f}{'-aa' if a else ''}" for f, a in EFFECTS])
def test_alpha_in_unit_range_into_and_out_of_every_lens(spec, size, filt, aa):
    pano = Camera.from_spec("equirect", (2 * W, W))
    cam = Camera.from_spec(spec, small(spec, size))
    src = rgba_pano(2 * W, W)
    out, cov = warp(src, pano, cam, filter=filt, antialias=aa, samples=1)
    assert_contract(out, cov)
    # and the lens as the source: its own picture, with alpha, back to a panorama
    img = rgba_pano(cam.width, cam.height, seed=1)
    out, cov = warp(img, cam, pano, filter=filt, antialias=aa, allow_parallax=True)
    assert_contract(out, cov)


# (a dual fisheye is no identity of itself: where its circles overlap, a source blends both readings)
IDENTITY = [c for c in ONE_PER_LENS if not c[0].startswith(("tiled", "dual-fisheye"))] + [
    ("optics:tca=1.001/0.999,vignetting=pa/-0.3/0.1/-0.05,base=perspective,fov=60", (W, 64))]


@pytest.mark.parametrize("spec,size", IDENTITY, ids=[c[0] for c in IDENTITY])
def test_identity_lens_changes_neither_colour_nor_alpha(spec, size):
    cam = Camera.from_spec(spec, small(spec, size))
    img = rgba_pano(cam.width, cam.height, seed=2)
    out, cov = warp(img, cam, cam, filter="bilinear", exact_map=True)
    full = cov == 1.0
    # a layout may show one direction in two places (Facebook's barrel margins, a part's edge): a pixel
    # whose direction comes back to another pixel reads that one, so only those that come back to
    # themselves are the identity
    ys, xs = np.mgrid[0:cam.height, 0:cam.width] + 0.5
    centres = np.stack([xs.ravel(), ys.ravel()], axis=-1)
    dirs, ok = cam.lens.pixel_to_dir(centres)
    back, ok2 = cam.lens.dir_to_pixel(dirs)
    home = ok & ok2 & (np.abs(np.asarray(back) - centres).max(axis=-1) < 1e-6)
    full &= home.reshape(cam.height, cam.width)
    falloff = falloff_image(cam.lens)
    if falloff is not None:  # light dimmed below MIN_FALLOFF (cos4 at 90 degrees) cannot be restored
        full &= falloff >= MIN_FALLOFF
    # pixels whose centre maps back to itself: the map is the identity to ~1e-9 px (the lens round
    # trip), so bilinear weights give the pixel itself to float32 rounding (2e-6 of values <= 1);
    # falloff divides and multiplies by the same float32 value (one rounding each)
    assert full.mean() > 0.3
    np.testing.assert_allclose(out[full], img[full], atol=2e-6)


def test_removing_vignetting_changes_colour_and_keeps_alpha():
    # a vignetting lens as the source: colour is divided by the falloff (un-vignetted), alpha is coverage
    # and is not; so straight colour (colour / alpha) equals the warp of the straight image without alpha
    cam = Camera.from_spec("optics:vignetting=pa/-0.6/0.1/-0.05,base=perspective,fov=70", (120, 80))
    view = Camera.from_spec("perspective:fov=40", (60, 40))
    rng = np.random.default_rng(3)
    straight = rng.random((80, 120, 3)).astype(np.float32) * 0.5 + 0.25
    a = np.float32(0.8)
    out, cov = warp(np.concatenate([straight * a, np.full((80, 120, 1), a)], -1), cam, view)
    plain, _ = warp(straight, cam, view)
    inside = cov == 1.0
    assert inside.all()
    np.testing.assert_allclose(out[..., 3], 0.8, atol=1e-6)  # not 0.8 / falloff (up to 1.6 at the corners)
    np.testing.assert_allclose(out[..., :3] / out[..., 3:], plain, rtol=1e-5)
    assert plain.max() > straight.max() * 1.1  # the falloff was removed: brighter than any source value


def test_lensfun_vignetting_source_keeps_alpha_at_most_one():
    pytest.importorskip("lensfunpy")
    spec = "lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=12,aperture=4"
    cam = Camera.from_spec(spec, (150, 100))
    pano = Camera.from_spec("equirect", (128, 64))
    img = np.ones((100, 150, 4), np.float32)
    out, cov = warp(img, cam, pano, filter="lanczos", samples=4)
    assert_contract(out, cov)
    lit = out[..., 3] > 0.999
    assert lit.any() and (out[..., 0][lit] > 1.05).any()  # colour un-vignetted above the source's 1


def test_dual_fisheye_blend_keeps_alpha_in_range():
    src = Camera.from_spec("dual-fisheye:fov=200", (2 * W, W))
    pano = Camera.from_spec("equirect", (2 * W, W))
    for filt, aa in EFFECTS:
        out, cov = warp(rgba_pano(2 * W, W, seed=4), src, pano, filter=filt, antialias=aa)
        assert_contract(out, cov)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-0.5, 1.5, width=32), min_size=1, max_size=20),
       st.lists(st.floats(0, 4, width=32), min_size=3, max_size=3))
def test_settle_rules(alphas, colour):
    # the rules of docs/conventions.md, transcribed: a > 1 -> 1 with colour / a (straight colour kept);
    # a < 0 -> 0 with colour 0; 0 <= a <= 1 untouched
    img = np.array([[colour + [a] for a in alphas]], np.float32)
    before = img.astype(np.float64)
    settle(img)
    for k, a in enumerate(before[0, :, 3]):
        got = img[0, k].astype(np.float64)
        if a > 1:
            # float32 division: 1e-6 relative, and float32's subnormal spacing (1.4e-45) below 1.2e-38
            np.testing.assert_allclose(got, list(before[0, k, :3] / a) + [1.0], rtol=1e-6, atol=1e-44)
        elif a < 0:
            assert (got == 0).all()
        else:
            assert (got == before[0, k]).all()


@pytest.mark.parametrize("filt", ["bicubic", "lanczos", "bilinear", "nearest", "antialias"])
@pytest.mark.parametrize("value", [np.finfo(np.float32).max, np.inf])
def test_finite_source_stays_finite(filt, value):
    # the largest float32 next to 0: Catmull-Rom and Lanczos overshoot by up to ~8 % and 13 %, which
    # would pass float32's range; +inf is read as the largest float32 (the engine says so) and likewise
    img = np.zeros((32, 64, 3), np.float32)
    img[:, 30:33] = value
    img[:, 33:] = -np.finfo(np.float32).max
    src = Camera.from_spec("equirect", (64, 32))
    dst = Camera.from_spec("perspective:fov=90", (41, 37))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the engine's note on non-finite source values
        if filt == "antialias":  # the footprint prefilter's mip levels average the largest values too
            out, _ = warp(img, src, Camera.from_spec("fisheye:fov=180", (12, 12)), antialias=True)
        else:
            out, _ = warp(img, src, dst, filter=filt, samples=4)
    assert np.isfinite(out).all()
    if filt == "antialias":  # each footprint averages the 3-column band with its neighbours: below the largest
        assert out.max() > 0.1 * np.finfo(np.float32).max
    else:
        assert out.max() == np.finfo(np.float32).max


def test_cli_writes_alpha_to_every_format_that_holds_it(tmp_path):
    # the formats' records decide: EXR, PNG and TIFF hold alpha, JPG and PPM do not
    import lenslab.io as lio
    from lenslab.cli.main import main
    from lenslab.io.registry import formats

    pano = np.zeros((32, 64, 3), np.float32) + 0.5
    lio.write(tmp_path / "p.exr", pano)
    for name, fmt in formats().items():
        if not fmt.writable or fmt.kind != "image" or 3 not in fmt.channels:
            continue
        out = tmp_path / f"o{fmt.extensions[0]}"
        assert main(["warp", str(tmp_path / "p.exr"), "-o", str(out), "--to", "fisheye:fov=180", "--size", "24x24",
                     "-q"]) == 0, name
        img, meta = lio.read(out)
        assert (img.shape[2] == 4) == fmt.alpha, name
        if fmt.alpha:
            assert img[0, 0, 3] == 0 and img[12, 12, 3] == 1  # outside and inside the image circle


@pytest.mark.shared_data
def test_removing_a_real_lens_vignetting_keeps_alpha_at_most_one(shared_data, tmp_path):
    # the round trip of a user's report: a real panorama into a vignetting fisheye profile, then that
    # fisheye (its camera stored in the EXR) back to a panorama
    import lenslab.io as lio

    pytest.importorskip("lensfunpy")
    lens = "lensfun:lens=Samyang 8mm f/2.8 UMC Fish-eye,crop=1.534,aperture=2.8"
    run = lambda *a: subprocess.run([sys.executable, "-m", "lenslab", "warp", *map(str, a), "-q"],  # noqa: E731
                                    capture_output=True, text=True)
    r = run(shared_data / "hdri" / "forest.exr", "-o", tmp_path / "s.exr", "--to", lens, "--size", "450x300")
    assert r.returncode == 0, r.stderr
    r = run(tmp_path / "s.exr", "-o", tmp_path / "b.exr", "--to", "equirect", "--size", "256x128")
    assert r.returncode == 0, r.stderr
    back, _ = lio.read(tmp_path / "b.exr")
    assert back[..., 3].min() >= 0 and back[..., 3].max() <= 1  # was up to 6.23
    fish, _ = lio.read(tmp_path / "s.exr")
    assert fish[..., 3].max() <= 1


def test_display_transform_keeps_straight_colour_in_png_and_over_black_without_alpha(tmp_path):
    # a premultiplied pixel of straight colour 0.18 at alpha 0.5 through OpenColorIO's sRGB display
    # (Un-tone-mapped view: the sRGB curve): PNG holds the straight colour's code with the alpha, JPG the
    # colour over black; read back by OpenImageIO as stored (no premultiplication of its own)
    oiio = pytest.importorskip("OpenImageIO")
    import lenslab.io as lio
    from lenslab.cli.main import main

    img = np.zeros((8, 8, 4), np.float32)
    img[..., :3], img[..., 3] = 0.18 * 0.5, 0.5
    lio.write(tmp_path / "a.exr", img)
    enc = lambda x: 1.055 * x ** (1 / 2.4) - 0.055  # noqa: E731  (sRGB, IEC 61966-2-1, above the toe)
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    for name, want in (("a.png", [enc(0.18)] * 3 + [128 / 255]), ("a.jpg", [enc(0.09)] * 3)):
        assert main(["tonemap", str(tmp_path / "a.exr"), "-o", str(tmp_path / name), "--display", "sRGB",
                     "--view", "Un-tone-mapped", "-q"]) == 0
        inp = oiio.ImageInput.open(str(tmp_path / name), config)
        got = np.asarray(inp.read_image("float"))[4, 4]
        inp.close()
        # one 8-bit code: rounding (half a code) and OpenColorIO's float32 evaluation of the curve
        np.testing.assert_allclose(got, want, atol=1 / 255)
