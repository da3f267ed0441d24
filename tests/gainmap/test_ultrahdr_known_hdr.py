"""Ultra HDR JPEGs written in the test from known HDR content (tests/gainmap/files.py, from the specifications):
lenslab reads back the HDR within what the 8-bit gain map can hold, its formula and sampling agree with the
specification's formula transcribed in float64 on Pillow's decoding, and ':sdr' reads the SDR base."""

from __future__ import annotations

import io
import warnings

import numpy as np
import pytest
from PIL import Image

import lenslab.io as lio
from tests.gainmap.files import (apply_formula, bilinear_at_centres, jpeg, srgb_decode, srgb_encode,
                                 ultrahdr)

K = 1 / 64  # the specification's default offsets, written explicitly here


def _pillow(blob: bytes) -> np.ndarray:
    a = np.asarray(Image.open(io.BytesIO(blob)))
    return a[..., None] if a.ndim == 2 else a


def _known_hdr(channels: int, seed: int) -> np.ndarray:
    """48 x 64 linear HDR, constant over each 8 x 8 block (a flat block is coded exactly by a quality-100 JPEG's
    DC term), from 0.002 to 6 (2.6 stops above SDR white)."""
    rng = np.random.default_rng(seed)
    blocks = np.exp2(rng.uniform(np.log2(0.002), np.log2(6.0), (6, 8, channels)))
    return np.kron(blocks, np.ones((8, 8, 1)))


@pytest.mark.parametrize("channels", [1, 3])
def test_the_known_hdr_is_read_back_within_the_gain_maps_quantisation(tmp_path, channels):
    hdr = _known_hdr(channels, seed=channels)
    base_blob = jpeg(np.round(srgb_encode(np.minimum(hdr, 1.0)) * 255))
    sdr = srgb_decode(_pillow(base_blob) / 255.0)  # the base as a decoder gives it: the gain map is made from it
    log_gain = np.log2((hdr + K) / (sdr + K))
    lo, hi = log_gain.min(axis=(0, 1)), log_gain.max(axis=(0, 1))
    codes = np.round((log_gain - lo) / (hi - lo) * 255)
    gain_blob = jpeg(codes)
    coding_error = np.abs(_pillow(gain_blob).astype(float) - codes).max()  # what the gain map's JPEG changed
    seq = (lambda v: [f"{x:.9f}" for x in v]) if channels == 3 else (lambda v: f"{v[0]:.9f}")
    path = tmp_path / "known.jpg"
    path.write_bytes(ultrahdr(base_blob, gain_blob, {"GainMapMin": seq(lo), "GainMapMax": seq(hi), "OffsetSDR": K,
                                                     "OffsetHDR": K, "HDRCapacityMax": f"{hi.max():.9f}"}))
    raw, _ = lio.read(path, raw=True)
    np.testing.assert_array_equal(np.round(raw * 255), _pillow(base_blob))  # OpenCV and Pillow: the same base
    ours, meta = lio.read(path)
    assert meta["attributes"]["rendition"].startswith("HDR") and not meta["display_encoded"]
    # a gain map code is within 0.5 (rounding) + coding_error steps of the exact log gain; one step is
    # (hi - lo) / 255 stops; the 9 printed digits of the metadata and float32 add < 1e-6
    tolerance = (hi - lo) * (0.5 + coding_error) / 255 + 1e-6
    err = np.abs(np.log2((ours.astype(np.float64) + K) / (hdr + K)))
    assert ours.shape == hdr.shape and (err <= tolerance).all(), (err.max(), tolerance)
    assert hdr.max() > 1.5 and ours.max() > 1.5  # the highlights above SDR white are back


def test_a_smaller_gain_map_is_sampled_at_the_base_pixel_centres(tmp_path):
    """Gain map 16 x 8, left half code 0, right half 255 (flat 8 x 8 blocks: coded exactly); base 32 x 16 white;
    GainMapMax 2 stops. Base column x (centre x + 0.5) is at x / 2 - 0.25 in gain-map pixels: columns 15 and 16
    fall a quarter and three quarters of the way from gain-map column 7 to 8, so their log boost is 0.5 and 1.5."""
    gain = np.zeros((8, 16), np.uint8)
    gain[:, 8:] = 255
    path = tmp_path / "edge.jpg"
    path.write_bytes(ultrahdr(jpeg(np.full((16, 32), 255)), jpeg(gain), {"GainMapMin": 0, "GainMapMax": 2,
                                                                         "OffsetSDR": 0, "OffsetHDR": 0,
                                                                         "HDRCapacityMax": 2}))
    ours, _ = lio.read(path)
    want = np.array([1.0] * 15 + [2 ** 0.5, 2 ** 1.5] + [4.0] * 15)
    np.testing.assert_allclose(ours[:, :, 0], np.broadcast_to(want, (16, 32)), rtol=1e-6)  # float32 exp2


def test_per_channel_gamma_offsets_and_upsampling_follow_the_formula_on_pillows_decoding(tmp_path):
    rng = np.random.default_rng(7)
    base_codes = np.round(rng.uniform(0, 255, (37, 61, 3)))
    gain_codes = np.round(rng.uniform(0, 255, (10, 16, 3)))
    base_blob, gain_blob = jpeg(base_codes, 92), jpeg(gain_codes, 90)
    meta = {"GainMapMin": [-0.5, 0.0, 0.25], "GainMapMax": [2.0, 3.0, 1.5], "Gamma": [1.0, 2.0, 0.5],
            "OffsetSDR": [0.01, 0.02, 0.03], "OffsetHDR": [0.005, 0.0, 0.015], "HDRCapacityMin": 0.5,
            "HDRCapacityMax": 3.0}
    path = tmp_path / "formula.jpg"
    path.write_bytes(ultrahdr(base_blob, gain_blob, meta))
    sdr = srgb_decode(_pillow(base_blob) / 255.0)
    r = bilinear_at_centres(_pillow(gain_blob) / 255.0, 37, 61)
    want = apply_formula(sdr, r, meta["GainMapMin"], meta["GainMapMax"], meta["Gamma"], meta["OffsetSDR"],
                         meta["OffsetHDR"])
    ours, got = lio.read(path)
    # float32 arithmetic on exact decoder codes: a few float32 ulps of each value (2^-24 = 6e-8 relative)
    np.testing.assert_allclose(ours, want, rtol=2e-6, atol=1e-7)
    assert "Gamma (1, 2, 0.5)" in got["attributes"]["gain_map"] and "headroom 3 stops" in got["attributes"]["gain_map"]


def test_the_sdr_selector_reads_the_base_image_as_before(tmp_path):
    rng = np.random.default_rng(3)
    base_blob = jpeg(np.round(rng.uniform(0, 255, (24, 40, 3))))
    path = tmp_path / "sdr.jpg"
    path.write_bytes(ultrahdr(base_blob, jpeg(np.full((6, 10), 200)), {"GainMapMax": 3, "HDRCapacityMax": 3}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # asking for the base is no reason for a note
        sdr, meta = lio.read(f"{path}:sdr")
    np.testing.assert_allclose(sdr, srgb_decode(_pillow(base_blob) / 255.0), rtol=0, atol=2e-7)  # float32 of it
    assert meta["display_encoded"] and "SDR base image" in meta["attributes"]["rendition"]
    hdr, _ = lio.read(f"{path}:hdr")
    assert hdr.max() > sdr.max() * 2  # code 200 of 3 stops: a boost of 2^(3 * 200 / 255) = 5.1 over the base


def test_a_selector_a_jpeg_does_not_take_is_one_line(tmp_path):
    path = tmp_path / "plain.jpg"
    path.write_bytes(jpeg(np.zeros((8, 8, 3))))
    from lenslab.errors import FormatError

    with pytest.raises(FormatError, match=r"':sdr'.*not ':left'"):
        lio.read(f"{path}:left")
    plain, _ = lio.read(f"{path}:sdr")  # a JPEG without a gain map is its own SDR image
    assert plain.shape == (8, 8, 3)


def test_info_names_the_rendition_and_the_headroom(tmp_path):
    from lenslab.cli.info import _text, describe

    path = tmp_path / "info.jpg"
    path.write_bytes(ultrahdr(jpeg(np.full((16, 16, 3), 128)), jpeg(np.full((8, 8), 255)),
                              {"GainMapMax": 2.5, "HDRCapacityMax": 2.5}))
    text = _text(describe(str(path)))
    assert "rendition: HDR" in text and "headroom 2.5 stops (5.66x SDR white)" in text  # 2^2.5 = 5.657
    assert "rendition: SDR base image" in _text(describe(f"{path}:sdr"))


def test_an_rgb_gain_map_applies_in_the_base_images_own_primaries(tmp_path):
    """A Display P3 base with an RGB gain map: the specifications apply the gain to the base's own linear RGB
    (P3), before any conversion; transcribed with colour-science's P3 -> Rec.709 matrix."""
    import colour

    from lenslab.io.colour.icc_build import profile

    rng = np.random.default_rng(11)
    base_codes = np.round(rng.uniform(0, 255, (16, 24, 3))).astype(np.uint8)
    buf = io.BytesIO()
    Image.fromarray(base_codes).save(buf, "JPEG", quality=95, subsampling=0, icc_profile=profile("Display P3"))
    gain_blob = jpeg(np.round(rng.uniform(0, 255, (8, 12, 3))))
    meta = {"GainMapMin": [0.0, 0.0, 0.0], "GainMapMax": [3.0, 0.5, 2.0], "OffsetSDR": 0, "OffsetHDR": 0,
            "HDRCapacityMax": 3.0}
    path = tmp_path / "p3.jpg"
    path.write_bytes(ultrahdr(buf.getvalue(), gain_blob, meta))
    p3, srgb = colour.RGB_COLOURSPACES["Display P3"], colour.RGB_COLOURSPACES["sRGB"]
    sdr_p3 = srgb_decode(_pillow(buf.getvalue()) / 255.0)
    r = bilinear_at_centres(_pillow(gain_blob) / 255.0, 16, 24)
    want = colour.RGB_to_RGB(apply_formula(sdr_p3, r, 0.0, meta["GainMapMax"], 1.0, 0.0, 0.0), p3, srgb)
    ours, _ = lio.read(path)
    sdr, _ = lio.read(f"{path}:sdr")
    # lenslab's P3 decode (the profile's s15Fixed16 colorants) against colour-science's ideal matrix, times the
    # largest gain (2^3), bounds the difference; float32 adds a few 6e-8 relative steps
    tolerance = np.abs(sdr - colour.RGB_to_RGB(sdr_p3, p3, srgb)).max() * 8 + 1e-6 * np.abs(want).max()
    assert np.abs(ours - want).max() <= tolerance, (np.abs(ours - want).max(), tolerance)
    in_709 = apply_formula(colour.RGB_to_RGB(sdr_p3, p3, srgb), r, 0.0, meta["GainMapMax"], 1.0, 0.0, 0.0)
    assert np.abs(in_709 - want).max() > 100 * tolerance  # applied after the conversion, it would be wrong
