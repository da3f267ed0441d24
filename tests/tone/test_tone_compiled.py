"""The compiled per-channel kernels of AgX and PBR Neutral (``lenslab.cxx_kernels``) against their NumPy
references and the float64 formulas transcribed in :mod:`tests.tone.test_tone_reference`.

PBR Neutral's compiled kernel runs the NumPy kernel's float32 steps in the same order: the same bits.
AgX's compiled kernel keeps w = log2 v, the sigmoid polynomial and the outset matrix in float64 and computes
the 2.2 power without a log or an exp, so it is closer to the formula than the NumPy kernel, not equal to it.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import tone
from lenslab.tone import kernels
from tests.tone.test_tone_reference import ATOL, REFERENCE, RTOL, scene

pytest.importorskip("lenslab.cxx_kernels")

# AgX, compiled, against the float64 formula: the float32 inset matrix moves v by ~1e-7 relative (w by 1.5e-7),
# y is rounded to float32 before the power (2.2 x 6e-8 relative) and the power itself leaves ~2 float32
# roundings: measured at most 1.33e-7 over the images below (the NumPy kernel: up to 1.1e-5). 2e-7 keeps a
# factor 1.5 above the measurement and is 50 times tighter than the bound the NumPy kernel is held to.
AGX_ATOL = 2e-7


def wide_image(seed=3):
    """Channels spread over 2^-30 .. 2^40, black, a sun and near-greys, as (64, 64, 3) float32."""
    rng = np.random.default_rng(seed)
    img = np.exp2(rng.uniform(-30, 40, (64, 64, 3)))
    img[0, :4] = [[0, 0, 0], [0.18, 0.18, 0.18], [1, 1, 1], [3e4, 3e4, 3e4]]
    img[1] = 0.18 * np.exp2(rng.normal(0, 3, (64, 1))) * (1 + 0.01 * rng.normal(size=(64, 3)))
    return img.astype(np.float32)


def run(name, img, native, **kw):
    saved = kernels.NATIVE
    kernels.NATIVE = None if native else False
    try:
        return tone.tonemap(img, name, **kw)
    finally:
        kernels.NATIVE = saved


def test_the_compiled_kernels_are_what_the_per_channel_mode_runs():
    assert getattr(tone.get_curve("agx").build({}, 1.0), "pixels", False)
    assert getattr(tone.get_curve("pbr-neutral").build({}, 1.0), "pixels", False)
    kernels.NATIVE, saved = False, kernels.NATIVE
    try:
        assert not getattr(tone.get_curve("agx").build({}, 1.0), "pixels", False)
    finally:
        kernels.NATIVE = saved


@pytest.mark.parametrize("ev", [0.0, 1.5, -3.0, 8.0])
def test_pbr_neutral_compiled_gives_the_numpy_kernels_bits(ev):
    for img in (scene(), wide_image()):
        got, want = run("pbr-neutral", img, True, exposure=ev), run("pbr-neutral", img, False, exposure=ev)
        np.testing.assert_array_equal(got.view(np.uint32), want.view(np.uint32))


@pytest.mark.parametrize("ev", [0.0, 1.5, -3.0, 8.0])
def test_agx_compiled_is_within_2e_7_of_the_float64_formula(ev):
    for img in (scene(), wide_image()):
        ref = REFERENCE["agx"](img.astype(np.float64) * 2.0 ** ev)
        got = run("agx", img, True, exposure=ev).astype(np.float64)
        np.testing.assert_allclose(got, ref, rtol=0, atol=AGX_ATOL)
        assert np.all(got[ref == 0] == 0)  # black stays exactly black
    # the NumPy reference kernel, which runs where the extension is not built, keeps its own bound
    img = scene()
    np.testing.assert_allclose(run("agx", img, False, exposure=ev), REFERENCE["agx"](img.astype(np.float64) * 2.0 ** ev),
                               rtol=RTOL, atol=ATOL)


def test_agx_compiled_at_published_values():
    # Wrensch's minimal AgX at middle grey: t = (log2 0.18 + 12.47393) / 16.500999, sigmoid, then ^2.2;
    # transcribed in float64 here (the inset and outset matrices are the identity on grey to 4 digits)
    t = (np.log2(0.18) + 12.47393) / (4.026069 + 12.47393)
    s = np.polyval([15.5, -40.14, 31.96, -6.868, 0.4298, 0.1191, -0.00232], t)
    got = tone.agx(np.float32([[0.18, 0.18, 0.18]]))[0].astype(np.float64)
    np.testing.assert_allclose(got, s ** 2.2, atol=2e-4)  # 2e-4: the matrices' rows sum to 1 within 1.4e-4
    np.testing.assert_allclose(got, REFERENCE["agx"](np.full((1, 3), np.float32(0.18), np.float64))[0],
                               rtol=0, atol=AGX_ATOL)


@pytest.mark.parametrize("name", ["agx", "pbr-neutral"])
def test_bad_values_are_repaired_as_the_numpy_path_repairs_them(name):
    img = wide_image(5)
    img[2, 3] = [np.nan, 0.5, 0.5]
    img[4, 5] = [np.inf, 0.1, 0.2]
    img[6, 7, 2] = -2.0
    img[8, 9] = [-np.inf, -0.0, 1.0]
    counts = []
    outs = []
    for native in (True, False):
        with pytest.warns(tone.ToneWarning) as caught:
            outs.append(run(name, img, native))
        w = next(c.message for c in caught if isinstance(c.message, tone.ToneWarning))
        counts.append((w.nan, w.posinf, w.negative))
    assert counts[0] == counts[1] == (1, 1, 2)
    np.testing.assert_array_equal(outs[0][4, 5], [1, 1, 1])  # a +inf channel: white
    clean = img.copy()
    clean[2, 3, 0] = clean[6, 7, 2] = clean[8, 9, 0] = 0
    clean[4, 5] = 0
    expect = run(name, clean, True)
    expect[4, 5] = 1
    np.testing.assert_array_equal(outs[0], expect)
    if name == "pbr-neutral":
        np.testing.assert_array_equal(outs[0], outs[1])


@pytest.mark.parametrize("name", ["agx", "pbr-neutral"])
def test_per_channel_grey_ramps_step_back_at_most_two_ulps(name):
    # per channel, a grey ramp goes through the curve's matrices in float32, so a channel may step back by a
    # rounding between neighbouring inputs (the strict order is the grey kernel's: test_tone_curves); the
    # compiled AgX keeps that within 2 float32 ulps of 1 (the NumPy kernel stepped back by up to 3.7e-6)
    for centre in (0.003, 0.18, 1.0, 7.2, 1000.0):
        base = np.float32(centre).view(np.int32)
        xs = (base + np.arange(-5000, 5000, dtype=np.int32)).view(np.float32)
        y = tone.tonemap(np.repeat(xs[:, None], 3, axis=1)[None], name)[0]
        assert np.diff(y, axis=0).min() >= -2.4e-7, f"{name} steps back near {centre}"


def test_compiled_kernels_refuse_mismatched_buffers():
    k = pytest.importorskip("lenslab.cxx_kernels")
    src = np.zeros((4, 3), np.float32)
    with pytest.raises(ValueError, match="same whole RGB pixels"):
        k.pbr_neutral_pixels(src, np.zeros((3, 3), np.float32), np.ones(8, np.float32))
    with pytest.raises(ValueError, match="out of range"):
        k.agx_pixels(src, np.zeros((4, 3), np.float32), np.eye(3), np.eye(3), np.ones(7), 10.0, 2.0 ** -56, 2.0)
