"""The warp's per-band output hook (``on_band``) and the encoder's planes filled band by band from it.

A warp hands each band's final rows to ``on_band`` as it draws them (a clip's encoder converts them to Y'CbCr on the
band's thread), or all rows once when its pixels change after the bands. The rows given must be the image returned:
a uniform panorama of radiance 2 seen through a 180-degree fisheye is 2 inside the image circle and 0 outside (an
analytic value). The Y'CbCr codes made band by band, with bands cut anywhere (a 4:2:0 chroma block split between two
bands), are colour-science's BT.1886 inverse EOTF and BT.709 Y'CbCr encoding of the same light, within the rounding
of a code that lies within 0.001 of a half (the bound of tests/io/test_video_ycbcr.py), and the codes of one pass
over the whole frame exactly."""

from __future__ import annotations

import threading
from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.io.video.clips import VideoInfo  # noqa: E402
from lenslab.io.video.ycbcr import RowsToYCbCr, linear_to_ycbcr, planes, ycbcr_frame  # noqa: E402
from lenslab.lenses import Camera  # noqa: E402
from lenslab.warp.batch import PlanCache  # noqa: E402


def _cams(side=48):
    return Camera.from_spec("equirect", (2 * side, side)), Camera.from_spec("fisheye:fov=180", (side, side))


def _collect():
    got, threads, lock = {}, set(), threading.Lock()

    def on_band(rows, sl):
        with lock:
            threads.add(threading.get_ident())
            for r in range(sl.start, sl.stop):
                got.setdefault(r, []).append(rows[r - sl.start].copy())
    return got, threads, on_band


@pytest.mark.parametrize("kept", [False, True])
def test_every_row_is_handed_over_once_as_returned(kept):
    src, dst = _cams()
    cache = PlanCache(band_points=48 * 5)  # bands of 5 rows: many bands
    pano = np.full((48, 96, 3), 2.0, np.float32)
    if kept:
        cache.plan(src, dst).prepare()  # kept as taps, as a clip's frames are
    got, _, on_band = _collect()
    out, alpha = cache.warp_frame(pano, src, dst, on_band=on_band)
    assert sorted(got) == list(range(48)) and all(len(v) == 1 for v in got.values())
    np.testing.assert_array_equal(np.stack([got[r][0] for r in range(48)]), out)
    y, x = np.mgrid[0:48, 0:48] + 0.5
    inside = np.hypot(x - 24, y - 24) < 23.0  # pixel centres well inside the 180-degree circle of radius 24
    outside = np.hypot(x - 24, y - 24) > 25.0
    assert np.allclose(out[inside], 2.0, atol=1e-6) and (out[outside] == 0).all()


def test_rows_changed_after_the_bands_are_handed_over_again():
    """A NaN in the source: the warp draws again from a finite source; the hook's last rows are what it returns."""
    src, dst = _cams()
    pano = np.full((48, 96, 3), 2.0, np.float32)
    pano[20:28, 40:56] = np.nan
    got, _, on_band = _collect()
    with pytest.warns(RuntimeWarning):
        out, _ = PlanCache(band_points=48 * 5).warp_frame(pano, src, dst, on_band=on_band)
    assert np.isfinite(out).all()
    np.testing.assert_array_equal(np.stack([got[r][-1] for r in range(48)]), out)


@pytest.mark.parametrize("h,w", [(37, 50), (64, 48)])
def test_planes_filled_band_by_band_are_colour_sciences_codes(h, w):
    info = VideoInfo(w, h, Fraction(24), 1, "h264", "yuv420p")  # BT.709, limited range, BT.1886
    lin = (np.random.default_rng(3).uniform(-0.1, 1.3, (h, w, 3)) ** 3).astype(np.float32)
    whole = [p.copy() for p in planes(linear_to_ycbcr(lin, info, "yuv420p"))]
    cuts = [0, 1, 6, 13, 14, 29, h]
    fill = RowsToYCbCr(info, "yuv420p", False, ycbcr_frame(w, h, "yuv420p"))
    for a, b in reversed(list(zip(cuts[:-1], cuts[1:]))):  # in any order, as threads finish
        fill(lin[a:b], slice(a, b))
    got = [p[:-(-h // (2 if k else 1)), :-(-w // (2 if k else 1))].astype(np.int64)
           for k, p in enumerate(planes(fill.finish(lin)))]
    for g, p in zip(got, whole):
        np.testing.assert_array_equal(g, p[:g.shape[0], :g.shape[1]])
    e = colour.models.eotf_inverse_BT1886(np.clip(lin.astype(np.float64), 0, 1), L_B=0, L_W=1)
    ycc = colour.RGB_to_YCbCr(e, K=colour.WEIGHTS_YCBCR["ITU-R BT.709"], out_bits=8, out_legal=True,
                              out_int=False) * 255.0
    pad = np.full((-(-h // 2) * 2, -(-w // 2) * 2, 3), np.nan)
    pad[:h, :w] = ycc
    chroma = np.nanmean(pad.reshape(pad.shape[0] // 2, 2, pad.shape[1] // 2, 2, 3), axis=(1, 3))
    for g, want in zip(got, [ycc[..., 0], chroma[..., 1], chroma[..., 2]]):
        near_half = np.abs(want - np.floor(want) - 0.5) < 0.001
        assert ((g == np.round(want)) | ((np.abs(g - np.round(want)) <= 1) & near_half)).all()
