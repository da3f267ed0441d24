"""Deep EXR files written here with OpenEXR's bindings, read flattened, against OpenEXR's "Interpreting
OpenEXR Deep Pixels" transcribed in float64 in this test: samples sorted by Z, point samples at the same
depth merged with the document's formula (several opaque ones: the mean of their colours, lenslab's reading
of the document's rule for two), composited front to back with "over", colour premultiplied.

Decided behaviour, pinned here: a pixel without samples is 0 (alpha 0) with Z = +inf; a NaN colour of a
visible sample makes that channel NaN, behind an opaque sample it is hidden; an infinite colour stays
infinite; a sample with a NaN Z is dropped; a NaN alpha makes the alpha NaN and every sample behind it NaN;
alpha outside [0, 1] is clamped (and counted in ``meta["deep"]``).

Volume samples (``ZBack > Z``) are checked against the document's definition of merging overlapping volumes:
splitting every sample into many thin slices (alpha ``1 - (1 - a)**r``, colour ``c * alpha' / a``),
interleaving them and compositing with "over". With M slices per interval the order of two samples' pieces
inside one slice is the only error: their alphas' product, about ``u_i u_j / M**2`` a slice for optical
depths ``u = -log(1 - a)``, so ``u_i u_j / M`` over the interval: below 1e-4 here (u < 1.4, M = 20000; the
differences measured are at most 4.6e-6 and halve when M doubles). And any mix of point and volume samples
(hypothesis) against the document's procedure written out one piece at a time: split (its example code),
merge, sort, composite, to float64 rounding.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

import lenslab.io as lio
from lenslab.io.exr.flatten import flatten
from tests.io.deep_files import deep_header

OpenEXR = pytest.importorskip("OpenEXR")
H, W = 9, 11
F32 = 2.0 ** -23  # one float32 rounding of the float64 result


def merge_group(alphas, colours):
    """The document's merge of samples at one depth (alpha, colour list), pairwise left to right, as its
    example code computes it (``a1 + a2 - a1 a2``, ``log1p``: exact for tiny alphas). A merged sample
    carries its optical depth ``u = -log(1 - alpha)``, ``u1 + u2`` by the document's definition, rather than
    taking it back from an alpha rounded to 1. Where opaque samples are among them: alpha 1 and the mean of
    their colours."""
    opaque = [i for i, a in enumerate(alphas) if a == 1]
    if opaque:
        return 1.0, [sum(colours[i][k] for i in opaque) / len(opaque) for k in range(len(colours[0]))]
    a1, c1, u1 = alphas[0], list(colours[0]), -math.log1p(-alphas[0])
    for a2, c2 in zip(alphas[1:], colours[1:]):
        u2 = -math.log1p(-a2)
        am = a1 + a2 - a1 * a2
        v1 = u1 / a1 if a1 > 0 else 1.0
        v2 = u2 / a2 if a2 > 0 else 1.0
        w = am / (u1 + u2) if u1 + u2 != 0 else 1.0
        c1 = [w * (x * v1 + y * v2) for x, y in zip(c1, c2)]
        a1, u1 = am, u1 + u2
    return a1, c1


def reference(zs, alphas, colours):
    """(alpha, colours, front Z) of one pixel's point samples, float64."""
    keep = [i for i in range(len(zs)) if not math.isnan(zs[i])]
    order = sorted(keep, key=lambda i: zs[i])
    groups = []
    for i in order:
        a = alphas[i] if math.isnan(alphas[i]) else min(max(alphas[i], 0.0), 1.0)
        if groups and groups[-1][0] == zs[i]:
            groups[-1][1].append(a)
            groups[-1][2].append(colours[i])
        else:
            groups.append((zs[i], [a], [colours[i]]))
    t, out, front = 1.0, [0.0] * len(colours[0]) if colours else [0.0, 0.0, 0.0], math.inf
    for z, a_list, c_list in groups:
        a, c = (a_list[0], list(c_list[0])) if len(a_list) == 1 else merge_group(a_list, c_list)
        if t == 0:
            break
        if a > 0 and front == math.inf:
            front = z
        out = [o + t * v for o, v in zip(out, c)]
        t = t * (1 - a)
    return 1 - t, out, front


def deep_file(path, pixels, zback=None, tiles=None):
    """A deep scanline file (RGBA half, Z float, ZBack float if given) from {(y, x): [(z, a, r, g, b), ...]};
    ``tiles`` (x size, y size): a deep tiled file."""
    chans = {n: np.empty((H, W), dtype=object) for n in ("R", "G", "B", "A", "Z")}
    if zback is not None:
        chans["ZBack"] = np.empty((H, W), dtype=object)
    for (y, x), samples in pixels.items():
        if not samples:
            continue
        s = np.array(samples, np.float64)
        chans["Z"][y, x] = s[:, 0].astype(np.float32)
        for i, n in enumerate("ARGB"):
            chans[n][y, x] = s[:, 1 + i].astype(np.float16)
        if zback is not None:
            chans["ZBack"][y, x] = np.array(zback[(y, x)], np.float32)
    OpenEXR.File(deep_header(OpenEXR.ZIPS_COMPRESSION, tiles), chans).write(str(path))
    return path


def stored(samples):
    """The samples as the file holds them (alpha and colour half, Z float)."""
    return [(float(np.float32(z)), *(float(np.float16(v)) for v in rest)) for z, *rest in samples]


def random_pixels(seed=7):
    rng = np.random.default_rng(seed)
    pixels = {}
    depths = np.array([1.0, 2.5, 3.0, 4.25, 7.0])  # few depths: samples at one depth happen often
    for y in range(1, H):
        for x in range(W):
            n = int(rng.integers(0, 6))
            a = rng.choice([0.0, 1.0, -1], size=n, p=[0.15, 0.15, 0.7])
            a = np.where(a < 0, rng.uniform(0.01, 0.99, n), a)
            z = np.where(rng.random(n) < 0.5, rng.choice(depths, n), rng.uniform(0.5, 9, n))
            rgb = a[:, None] * rng.uniform(0, 2, (n, 3))
            pixels[(y, x)] = [(z[i], a[i], *rgb[i]) for i in rng.permutation(n)]  # random order in depth
    return pixels


SPECIAL = {
    (0, 0): [],
    (0, 1): [(2.0, 0.5, math.nan, 0.2, 0.3), (3.0, 0.5, 0.1, 0.1, 0.1)],  # NaN red in front: red NaN
    (0, 2): [(5.0, 0.5, math.nan, 0.2, 0.3), (1.0, 1.0, 0.4, 0.5, 0.6)],  # NaN behind an opaque sample: hidden
    (0, 3): [(2.0, 0.5, 0.1, math.inf, 0.3), (1.0, 0.25, 0.1, 0.1, 0.1)],  # +inf green, visible: inf
    (0, 4): [(math.nan, 0.9, 0.9, 0.9, 0.9), (1.0, 0.5, 0.2, 0.2, 0.2)],  # NaN depth: dropped
    (0, 5): [(1.0, math.nan, 0.2, 0.2, 0.2), (2.0, 0.5, 0.3, 0.3, 0.3)],  # NaN alpha: NaN behind it
    (0, 6): [(3.0, 0.5, 0.3, 0.3, 0.3), (1.0, 1.0, 0.7, 0.1, 0.2), (2.0, 1.0, 0.9, 0.9, 0.9)],  # opaque front
    (0, 7): [(1.0, 0.0, 0.1, 0.2, 0.3), (2.0, 0.0, 0.1, 0.1, 0.1)],  # alpha 0: light added, no coverage
    (0, 8): [(1.0, 1.5, 0.3, 0.3, 0.3), (2.0, 0.5, 0.9, 0.9, 0.9)],  # alpha beyond 1: clamped to 1
    (0, 9): [(4.0, 1.0, 0.2, 0.4, 0.6), (4.0, 1.0, 0.6, 0.0, 0.2), (4.0, 0.5, 0.9, 0.9, 0.9)],  # opaque, same Z
}


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    pixels = {**random_pixels(), **SPECIAL}
    path = deep_file(tmp_path_factory.mktemp("deep") / "points.exr", pixels)
    image, meta = lio.read(path, extra_channels=True)
    return pixels, image, meta


def test_every_pixel_is_the_document_s_flatten(synthetic):
    pixels, image, meta = synthetic
    assert image.shape == (H, W, 4) and meta["channels"] == ["R", "G", "B", "A"]
    z_plane = meta["extra_planes"]["Z"]
    for (y, x), samples in pixels.items():
        s = stored(samples)
        a, c, front = reference([v[0] for v in s], [v[1] for v in s], [v[2:] for v in s])
        np.testing.assert_allclose(image[y, x], np.array([*c, a], np.float32), rtol=4 * F32, atol=1e-30,
                                   equal_nan=True, err_msg=f"pixel {(y, x)}: {samples}")
        assert z_plane[y, x] == np.float32(front) or (math.isinf(front) and np.isposinf(z_plane[y, x]))


def test_a_deep_tiled_file_reads_as_the_scanline_one(synthetic, tmp_path):
    pixels, image, meta = synthetic
    tiled, tmeta = lio.read(deep_file(tmp_path / "tiled.exr", pixels, tiles=(4, 3)), extra_channels=True)
    assert tmeta["storage"] == "deeptile" and tmeta["deep"] == meta["deep"]
    np.testing.assert_array_equal(tiled, image)
    np.testing.assert_array_equal(tmeta["extra_planes"]["Z"], meta["extra_planes"]["Z"])


def test_the_decided_values_at_the_edges(synthetic):
    _, image, meta = synthetic
    assert not image[0, 0].any() and np.isposinf(meta["extra_planes"]["Z"][0, 0])
    assert np.isnan(image[0, 1, 0]) and np.isfinite(image[0, 1, 1:]).all()
    assert np.isfinite(image[0, 2]).all() and image[0, 2, 3] == 1
    assert np.isposinf(image[0, 3, 1]) and np.isfinite(image[0, 3, [0, 2, 3]]).all()
    np.testing.assert_array_equal(image[0, 4], np.float16([0.2, 0.2, 0.2, 0.5]).astype(np.float32))
    assert np.isnan(image[0, 5, 3]) and np.isnan(image[0, 5, :3]).all()
    np.testing.assert_array_equal(image[0, 6], np.float16([0.7, 0.1, 0.2, 1.0]).astype(np.float32))
    np.testing.assert_allclose(image[0, 7], np.float16([0.1, 0.2, 0.3, 0]).astype(np.float32) +
                               np.float16([0.1, 0.1, 0.1, 0]).astype(np.float32), rtol=F32)
    np.testing.assert_array_equal(image[0, 8], np.float16([0.3, 0.3, 0.3, 1]).astype(np.float32))
    opaque = np.float16([[0.2, 0.4, 0.6], [0.6, 0.0, 0.2]]).astype(np.float64)  # the mean of the opaque two
    np.testing.assert_allclose(image[0, 9], np.float32([*opaque.mean(0), 1]), rtol=F32)
    assert meta["deep"]["dropped_nan_z"] == 1 and meta["deep"]["alpha_clamped"] == 1
    assert meta["deep"]["samples"] == sum(len(v) for v in {**random_pixels(), **SPECIAL}.values())


point = st.tuples(st.sampled_from([0.5, 1.0, 2.0]) | st.floats(0, 100), st.sampled_from([0.0, 1.0]) |
                  st.floats(0, 1), st.floats(-2, 2), st.floats(0, 3))


@given(st.lists(st.lists(point, max_size=7), min_size=1, max_size=5))
@example([[(0.5, 0.0, 0.0, 0.0), (0.5, 2.2250738585e-313, 0.0, 0.0), (0.5, 0.0, 0.0, 1.0)]])  # a tiny alpha
def test_flatten_is_the_document_s_for_any_order_and_ties(pixel_samples):
    pix = np.array([p for p, s in enumerate(pixel_samples) for _ in s], np.int64)
    rows = [v for s in pixel_samples for v in s]
    arr = np.array(rows, np.float64).reshape(len(rows), 4)
    a, c, front, _ = flatten(pix, arr[:, 0], None, arr[:, 1], arr[:, 2:], len(pixel_samples))
    for p, s in enumerate(pixel_samples):
        ra, rc, rf = reference([v[0] for v in s], [v[1] for v in s], [list(v[2:]) for v in s]) if s else \
            (0.0, [0.0, 0.0], math.inf)
        np.testing.assert_allclose([*c[p], a[p]], [*rc, ra], rtol=1e-9, atol=1e-12)
        assert front[p] == rf


def sliced(samples, m):
    """One pixel of point and volume samples [(z, zback, a, c)] flattened by cutting every volume into thin
    slices between each pair of the pixel's depths (m slices each), interleaved, composited with over."""
    bounds = sorted({v for z, zb, _, _ in samples for v in (z, zb)})
    layers = []  # (depth, order, alpha, colour)
    for z, zb, a, c in samples:
        if zb <= z:
            layers.append((z, 0, 0, a, c))
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        edges = np.linspace(lo, hi, m + 1)
        for k in range(m):
            for j, (z, zb, a, c) in enumerate(samples):
                if zb > z and z <= edges[k] and edges[k + 1] <= zb:
                    r = (edges[k + 1] - edges[k]) / (zb - z)
                    ap = 1 - (1 - a) ** r
                    layers.append((edges[k], 1, j, ap, c * ap / a if a > 0 else c * r))
    layers.sort(key=lambda v: v[:3])
    t, out = 1.0, 0.0
    for *_, a, c in layers:
        if t == 0:
            break
        out += t * c
        t *= 1 - a
    return 1 - t, out


VOLUMES = {  # (z, zback, alpha, colour premultiplied)
    (0, 0): [(1.0, 3.0, 0.6, 0.3)],  # one volume sample
    (0, 1): [(1.0, 3.0, 0.6, 0.3), (2.0, 5.0, 0.5, 0.4)],  # two overlapping in part
    (0, 2): [(1.0, 3.0, 0.75, 0.75), (2.0, 2.0, 1.0, 7.0)],  # an opaque point inside a volume
    (0, 3): [(1.0, 2.0, 0.6, 0.3), (1.0, 2.0, 0.3, 0.2)],  # two coinciding volumes
    (0, 4): [(1.0, 4.0, 0.5, 0.2), (2.0, 3.0, 1.0, 0.9)],  # an opaque volume inside another
    (0, 5): [(1.0, 3.0, 0.0, 0.4), (2.0, 4.0, 0.7, 0.2)],  # light without absorption over a volume
    (0, 6): [(1.0, 3.0, 0.5, 0.2), (1.0, 1.0, 0.5, 0.1), (3.0, 3.0, 0.5, 0.3)],  # points at its front and back
}


def test_volume_samples_are_the_limit_of_thin_interleaved_slices(tmp_path):
    pixels = {k: [(z, a, c, c, c) for z, _, a, c in v] for k, v in VOLUMES.items()}
    zback = {k: [zb for _, zb, _, _ in v] for k, v in VOLUMES.items()}
    image, _ = lio.read(deep_file(tmp_path / "volumes.exr", pixels, zback), data_window=True)
    for (y, x), samples in VOLUMES.items():
        s = [(z, zb, float(np.float16(a)), float(np.float16(c))) for z, zb, a, c in samples]
        a, c = sliced(s, 20000)
        np.testing.assert_allclose(image[y, x], [c, c, c, a], atol=1e-4, err_msg=f"pixel {(y, x)}: {samples}")
    h = lambda *v: [float(np.float16(x)) for x in v]  # noqa: E731 (the values as the file stores them)
    np.testing.assert_allclose(image[0, 0], np.float32(h(0.3, 0.3, 0.3, 0.6)), rtol=4 * F32)  # alone: as stored
    a, c = merge_group(h(0.6, 0.3), [h(0.3), h(0.2)])  # coinciding volumes: the merge formula
    np.testing.assert_allclose(image[0, 3], np.float32([c[0], c[0], c[0], a]), rtol=4 * F32)
    # a volume of alpha 0.75 split in half by an opaque point: 0.5 of its light, then the point's
    np.testing.assert_allclose(image[0, 2], np.float32([4.0, 4.0, 4.0, 1.0]), rtol=4 * F32)


def tidy_reference(samples):
    """One pixel's samples [(z, zback, a, c)] flattened by the document's procedure, written out: each volume
    sample split at every depth where another sample starts or ends inside it (the document's split, as
    its example code computes it: alpha ``-expm1(x log1p(-a))`` = ``1 - (1 - a)**x``, colour
    ``c * alpha' / a``; ``a x`` and ``c x`` for alphas below the smallest normal number), pieces with the
    same front and back merged, sorted by front then back, composited front to back with over."""
    bounds = sorted({v for z, zb, _, _ in samples for v in (z, zb) if not math.isnan(v)})
    pieces = {}
    for z, zb, a, c in samples:
        if math.isnan(z):
            continue
        a = min(max(a, 0.0), 1.0)
        if not (zb > z and math.isfinite(z) and math.isfinite(zb)):
            pieces.setdefault((z, z), []).append((a, c))
            continue
        cuts = [z] + [b for b in bounds if z < b < zb] + [zb]
        for lo, hi in zip(cuts[:-1], cuts[1:]):
            x = (hi - lo) / (zb - z)
            if a == 1:
                ap, cp = 1.0, c
            elif a > sys.float_info.min:
                ap = -math.expm1(x * math.log1p(-a))
                cp = ap / a * c
            else:
                ap, cp = a * x, c * x
            pieces.setdefault((lo, hi), []).append((ap, cp))
    t, out_a, out_c = 1.0, 0.0, 0.0
    for key in sorted(pieces):
        alphas, colours = [p[0] for p in pieces[key]], [[p[1]] for p in pieces[key]]
        a, c = (alphas[0], colours[0]) if len(alphas) == 1 else merge_group(alphas, colours)
        if t == 0:
            break
        out_c += t * c[0]
        t *= 1 - a
    return 1 - t, out_c


depth = st.sampled_from([0.0, 0.5, 1.0, 2.0, 3.5])
sample = st.tuples(depth, st.sampled_from([0.0, 0.0, 0.25, 1.0, 1.5]), st.sampled_from([0.0, 1.0, 1e-300]) |
                   st.floats(0, 1), st.floats(0, 2))


@given(st.lists(st.lists(sample, min_size=1, max_size=6), min_size=1, max_size=4))
def test_points_and_volumes_flatten_as_the_document_s_procedure_written_out(pixel_samples):
    """Any mix of point and volume samples, overlapping in part, in full or not at all, opaque or not:
    the sweep over each pixel's depths gives what splitting, merging and compositing one piece at a time
    gives, to float64 rounding."""
    rows = [(p, z, z + length, a, c) for p, s in enumerate(pixel_samples) for z, length, a, c in s]
    arr = np.array(rows, np.float64)
    a, c, _, _ = flatten(arr[:, 0].astype(np.int64), arr[:, 1], arr[:, 2], arr[:, 3], arr[:, 4:], len(pixel_samples))
    for p, s in enumerate(pixel_samples):
        ra, rc = tidy_reference([(z, z + length, al, co) for z, length, al, co in s])
        np.testing.assert_allclose([c[p, 0], a[p]], [rc, ra], rtol=1e-9, atol=1e-12)
