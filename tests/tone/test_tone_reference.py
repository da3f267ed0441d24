"""Every tone curve against one float64 reference transcribed here from its published source, through
every kernel the curve has: on single values (grey images, and the grey form of the RGB curves), on
RGB triples per channel, and on luminance (RGB scaled by curve(L) / L, blended toward grey where a
channel would pass 1). Swapping any one curve's formula for another's fails these tests.

Sources: Reinhard et al. 2002 eqs. 3-4; Hable, "Filmic Tonemapping Operators" (2010) with the blog
constants; Narkowicz, "ACES Filmic Tone Mapping Curve" (2016); Hill, BakingLab ACES.hlsl (2016);
Wrensch, "Minimal AgX Implementation" (2024); the Khronos PBR Neutral specification (README of
KhronosGroup/ToneMapping, written with F90 = 0.04, Ks = 0.8 - F90, Kd = 0.15); the sRGB EOTF from
colour-science.
"""

from __future__ import annotations

import colour
import numpy as np
import pytest

from lenslab import tone

W709 = np.array([0.2126, 0.7152, 0.0722])  # IEC 61966-2-1's Y row (colour-science's sRGB matrix)


def _hable_blog(x):
    A, B, C, D, E, F = 0.15, 0.50, 0.10, 0.20, 0.02, 0.30

    def f(v):
        return (v * (A * v + C * B) + D * E) / (v * (A * v + B) + D * F) - E / F
    return np.minimum(f(2.0 * x) / f(11.2), 1.0)


HILL_IN = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
HILL_OUT = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605],
                     [-0.00327, -0.07276, 1.07602]])


def _aces_hill(rgb):
    v = rgb @ HILL_IN.T
    fit = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081)
    return np.clip(fit @ HILL_OUT.T, 0.0, 1.0)


AGX_IN = np.array([[0.842479062253094, 0.0784335999999992, 0.0792237451477643],
                   [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
                   [0.0423756549057051, 0.0784336, 0.879142973793104]])
AGX_OUT = np.array([[1.19687900512017, -0.0980208811401368, -0.0990297440797205],
                    [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
                    [-0.0529716355144438, -0.0980434501171241, 1.15107367264116]])


def _agx(rgb):
    lo, hi = -12.47393, 4.026069
    v = np.clip(np.log2(np.maximum(rgb @ AGX_IN.T, 1e-10)), lo, hi)
    t = (v - lo) / (hi - lo)
    s = 15.5 * t**6 - 40.14 * t**5 + 31.96 * t**4 - 6.868 * t**3 + 0.4298 * t**2 + 0.1191 * t - 0.00232
    return np.clip(s @ AGX_OUT.T, 0.0, 1.0) ** 2.2


def _pbr_neutral(rgb):
    """The Khronos specification's equations, as written there (F90, Ks, Kd), vectorised."""
    f90, ks, kd = 0.04, 0.8 - 0.04, 0.15
    x = rgb.min(axis=-1, keepdims=True)
    f = np.where(x <= 2 * f90, x - x * x / (4 * f90), f90)
    c = rgb - f
    p = c.max(axis=-1, keepdims=True)
    pn = 1 - (1 - ks) ** 2 / (p + 1 - 2 * ks)
    g = 1 / (kd * (p - pn) + 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        shoulder = c * (pn / p) * g + pn * (1 - g)
    return np.where(p <= ks, c, shoulder)


#: name -> float64 reference on RGB triples (..., 3); the scalar curves act on each channel
REFERENCE = {
    "clamp": lambda x: np.minimum(x, 1.0),
    "gamma": lambda x: colour.models.eotf_sRGB(np.minimum(x, 1.0) ** (1 / 2.2)),
    "reinhard": lambda x: x / (1 + x),
    "reinhard-extended": lambda x: np.minimum(x * (1 + x / 4.0**2) / (1 + x), 1.0),
    "hable": _hable_blog,
    "aces": lambda x: np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0, 1),
    "aces-hill": _aces_hill,
    "agx": _agx,
    "pbr-neutral": _pbr_neutral,
}
RGB_CURVES = {"aces-hill", "agx", "pbr-neutral"}


def on_values(name, x):
    """The reference on single values: the curve itself, or for an RGB curve the luminance of its
    output on the grey (x, x, x)."""
    x = np.asarray(x, np.float64)
    out = REFERENCE[name](np.repeat(x[..., None], 3, axis=-1))
    return out @ W709 if name in RGB_CURVES else out[..., 0]


def on_luminance(name, rgb):
    """The luminance mode's definition: Ld = curve(L), RGB scaled by Ld / L, then blended toward
    (Ld, Ld, Ld) just enough that the brightest channel is at most 1."""
    lum = rgb @ W709
    ld = on_values(name, lum)
    scaled = rgb * (ld / np.maximum(lum, 1e-300))[..., None]
    peak = scaled.max(axis=-1)
    t = np.clip((1 - ld) / np.maximum(peak - ld, 1e-300), 0, 1)[..., None]
    return np.clip(ld[..., None] + (scaled - ld[..., None]) * t, 0, 1)


VALUES = np.array([0.0, 1e-6, 1e-4, 1e-3, 0.003, 0.01, 0.05, 0.08, 0.18, 0.5, 0.76, 0.8, 1.0, 2.0, 4.0, 5.6,
                   7.2, 8.0, 11.2, 100.0, 1e4])


def scene(seed=5):
    """A lognormal HDR image around middle grey with saturated colours, black and a sun."""
    rng = np.random.default_rng(seed)
    img = 0.18 * np.exp2(rng.normal(0, 2.5, (24, 32, 3)))
    img[0, :3] = [[0, 0, 0], [1e-5, 0, 0], [30000, 28000, 25000]]
    img[1, :4] = [[0.9, 0.05, 0.01], [0.02, 0.3, 0.95], [0.5, 0.5, 0.5], [0.6, 0.7, 0.3]]
    return img.astype(np.float32)


# Tolerances: float32 kernels against float64 formulas. A rational curve of a dozen rounded steps
# stays within 1e-5 relative. The log2/exp2 pairs of gamma and agx, agx's 6th-order polynomial and
# Hill's fit (which subtracts nearly equal numbers near v = 0.0032) leave up to 3.4e-6 absolute (about
# 30 float32 ulps of an output near 0.5): 1e-5 keeps a factor of 3 above that. The grey form of the
# RGB curves leaves out matrices whose rows sum to 1 within 1.4e-4, but weighed by the luminance
# weights those deviations cancel to below 1e-6, inside the same bound.
RTOL, ATOL = 1e-5, 1e-5


@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_published_reference_is_what_the_registry_holds(name):
    assert set(REFERENCE) | {"reinhard2002", "drago", "mantiuk"} == set(tone.CURVES), \
        "every per-pixel curve needs a reference here"
    assert tone.get_curve(name).kind == ("rgb" if name in RGB_CURVES else "scalar")


@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_value_kernel_and_grey_images_match_the_reference(name):
    x = VALUES.astype(np.float32)
    ref = on_values(name, x.astype(np.float64))
    np.testing.assert_allclose(tone.tonemap(x, name), ref, rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tone.tonemap(x.reshape(3, 7, 1), name)[..., 0], ref.reshape(3, 7),
                               rtol=RTOL, atol=ATOL)


@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_rgb_kernel_matches_the_reference(name):
    img = scene()
    got = tone.tonemap(img, name, mode="per-channel")
    np.testing.assert_allclose(got, REFERENCE[name](img.astype(np.float64)), rtol=RTOL, atol=ATOL)


@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_luminance_kernel_matches_the_reference(name):
    img = scene()
    got = tone.tonemap(img, name, mode="luminance")
    np.testing.assert_allclose(got, on_luminance(name, img.astype(np.float64)), rtol=RTOL, atol=ATOL)


@pytest.mark.parametrize("ev", [-2.0, 1.5])
@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_exposure_folded_into_each_kernel_is_a_multiplier_in_stops(name, ev):
    img = scene(7)
    ref = REFERENCE[name](img.astype(np.float64) * 2.0**ev)
    np.testing.assert_allclose(tone.tonemap(img, name, exposure=ev), ref, rtol=RTOL, atol=ATOL)


def test_published_values():
    # Hable's blog constants: f(2.0) / f(11.2) = 0.4929185 at x = 1 (bias 2.0); white at x = W / bias.
    # 1e-6: the value is given to 7 digits (5e-8) and the float32 result rounds by 3e-8
    assert float(tone.hable(np.float32([1.0]))[0]) == pytest.approx(0.4929185, abs=1e-6)
    assert float(tone.hable(np.float32([5.6]))[0]) == 1.0
    # Narkowicz at 1: 2.54 / 3.16 (1e-6 relative: a few float32 roundings of the rational form);
    # Reinhard eq. 3 at 1: 1/2; eq. 4 reaches 1 at Lw
    assert float(tone.aces(np.float32([1.0]))[0]) == pytest.approx(2.54 / 3.16, rel=1e-6)
    assert float(tone.reinhard(np.float32([1.0]))[0]) == 0.5
    assert float(tone.reinhard_extended(np.float32([4.0]), white=4.0)[0]) == 1.0
    # Khronos PBR Neutral, its first published guarantee: c_out = c_in - 0.04 wherever every channel
    # is in [0.08, 0.8] (base colours reproduced exactly)
    rng = np.random.default_rng(1)
    base = rng.uniform(0.08, 0.8, (500, 3)).astype(np.float32)
    np.testing.assert_allclose(tone.pbr_neutral(base), base - np.float32(0.04), atol=1e-7)  # one float32 subtraction
    # and its second: no hue shift (the output stays in the plane of the input and the white axis)
    bright = rng.uniform(0.0, 20.0, (500, 3))
    out = tone.pbr_neutral(bright.astype(np.float32)).astype(np.float64)
    normal = np.cross(bright, np.ones(3))
    # float32 outputs of size <= 1 against normals of size ~20: 1e-5 is a few ulps of the products
    assert np.abs(np.einsum("ij,ij->i", out, normal)).max() < 1e-5 * np.linalg.norm(normal, axis=1).max()


@pytest.mark.parametrize("name, mode", [("hable", "luminance"), ("agx", "per-channel"), ("reinhard", "per-channel")])
def test_threads_share_large_images_without_changing_a_bit(name, mode):
    # 640 x 640 RGB is 1.2 M values: past the size at which the sweep splits an image between threads
    img = np.tile(scene(9), (27, 20, 1))[:640, :640].copy()
    img[5, 7] = [np.nan, np.inf, -1.0]
    img[600, 3, 1] = -np.inf
    runs = []
    for threads in (1, 2, 3):
        with pytest.warns(tone.ToneWarning) as caught:
            out = tone.tonemap(img, name, mode=mode, threads=threads)
        w = next(c.message for c in caught if isinstance(c.message, tone.ToneWarning))
        runs.append((out, (w.nan, w.posinf, w.negative)))
    for out, counts in runs[1:]:
        np.testing.assert_array_equal(out, runs[0][0])
        assert counts == runs[0][1] == (1, 1, 2)
