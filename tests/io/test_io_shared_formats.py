"""Every file of the shared format collection is read correctly or refused with a clear FormatError.

The collection (OpenEXR and OpenImageIO test images; see its MANIFEST.txt) exists in CI; the
``shared_data`` fixture skips where it is absent.
"""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import cv2
import numpy as np
import pytest

import lenslab.io as lio
from lenslab.errors import FormatError

pytestmark = pytest.mark.shared_data

HERE = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "formats"
REFUSED = {  # file -> what the refusal must say
    "oiio-testsuite-pnm/bad-4552.pgm": "truncated",
    "oiio-testsuite-pnm/bad-4553.pgm": "digits",
    "oiio-testsuite-pnm/bomb-65000.pgm": "beyond the limit",
}
# where the collection is absent, one placeholder case lets the shared_data fixture do the skipping
ALL = sorted(str(p.relative_to(HERE)) for p in HERE.rglob("*")
             if p.is_file() and p.suffix.lower() in {".exr", ".pfm", ".ppm", ".pgm", ".pbm", ".jpg"}) \
    if HERE.is_dir() else ["(collection absent)"]


@pytest.fixture(scope="module")
def fmt(shared_data) -> Path:
    return shared_data / "formats"


@pytest.mark.parametrize("rel", ALL)
def test_every_file_read_or_refused(fmt, rel):
    path = fmt / rel
    if rel in REFUSED:
        with pytest.raises(FormatError, match=REFUSED[rel]) as info:
            lio.read(path)
        assert str(path) in str(info.value)
        return
    img, meta = lio.read(path)
    assert img.dtype == np.float32 and img.ndim == 3 and img.flags.c_contiguous
    assert meta["size"] == [img.shape[1], img.shape[0]] and len(meta["channels"]) == img.shape[2]
    hdr_jpeg = rel == "oiio-images/ultrahdr_sky.jpg"  # Ultra HDR: its HDR rendition, linear light (MANIFEST)
    assert meta["display_encoded"] == (meta["format"] not in ("exr", "pfm") and not hdr_jpeg)


def test_pnm_bombs_refused_without_allocating(fmt):
    for rel in ("bomb-65000.pgm", "bad-4553.pgm", "bad-4552.pgm"):
        tracemalloc.start()
        with pytest.raises(FormatError):
            lio.read(fmt / "oiio-testsuite-pnm" / rel)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert peak < 1 << 20, rel  # the 65000 x 65000 header would need 4 GB: refused from the header alone


def test_pnm_magic_beats_the_name(fmt):
    img, meta = lio.read(fmt / "oiio-testsuite-pnm/rgb-binary.ppm")
    assert meta["attributes"]["magic"] == "P3" and meta["attributes"]["encoding"] == "ascii"
    assert img.shape == (32, 32, 3)
    for name in ("rgb-binary.ppm", "rgb-ascii.ppm", "grey-ascii.pgm", "grey-binary.pgm"):
        ours, meta = lio.read(fmt / "oiio-testsuite-pnm" / name, raw=True)
        theirs = cv2.imread(str(fmt / "oiio-testsuite-pnm" / name), cv2.IMREAD_UNCHANGED)
        if theirs.ndim == 2:
            theirs = theirs[..., None]
        else:
            theirs = theirs[..., ::-1]
        np.testing.assert_array_equal(np.round(ours * meta["attributes"]["maxval"]), theirs)


def test_pbm_plain_and_raw(fmt):
    for name in ("bw-ascii.pbm", "bw-binary.pbm"):
        img, meta = lio.read(fmt / "oiio-testsuite-pnm" / name)
        theirs = cv2.imread(str(fmt / "oiio-testsuite-pnm" / name), cv2.IMREAD_GRAYSCALE)
        np.testing.assert_array_equal(img[..., 0], theirs / 255.0)  # 1 = black, 0 = white
        assert meta["bit_depth"] == 1


def test_pfm_both_byte_orders(fmt, tmp_path):
    for name in ("test-1.pfm", "test-2.pfm", "test-3.pfm"):
        ours, meta = lio.read(fmt / "oiio-images" / name)
        theirs = cv2.imread(str(fmt / "oiio-images" / name), cv2.IMREAD_UNCHANGED)
        np.testing.assert_array_equal(ours, theirs[..., ::-1])
    assert meta["attributes"]["byte_order"] == "big"
    # the big-endian file re-stored little-endian (payload byte-swapped, scale negated) reads the same
    data = (fmt / "oiio-images/test-3.pfm").read_bytes()
    head = b"PF\n240 240\n1.0\n"
    assert data.startswith(head)
    swapped = np.frombuffer(data[len(head):], ">f4").astype("<f4").tobytes()
    (tmp_path / "le.pfm").write_bytes(b"PF\n240 240\n-1.0\n" + swapped)
    le, meta = lio.read(tmp_path / "le.pfm")
    np.testing.assert_array_equal(le, ours)
    assert meta["attributes"]["byte_order"] == "little"


def test_all_half_values(fmt):
    img, meta = lio.read(fmt / "openexr-images/TestImages/AllHalfValues.exr")
    bits = img.astype(np.float16).view(np.uint16)  # back to half: lossless for every half value
    assert (bits[..., 0] == bits[..., 1]).all() and (bits[..., 0] == bits[..., 2]).all()  # a grey image
    assert np.unique(bits[..., 0]).size == 65536  # every half bit pattern survives, NaN payloads included
    r = img[..., 0]
    assert np.isnan(r).sum() == 2 * 1023  # exponent all ones, mantissa non-zero, either sign
    assert np.isposinf(r).sum() == 1 and np.isneginf(r).sum() == 1
    assert (r == 0).sum() == 2 and np.nanmin(np.abs(r[r != 0])) == np.float32(2.0 ** -24)  # +-0; smallest denormal
    assert meta["sample_type"] == "half"


def test_nan_inf_counted(fmt):
    import OpenEXR

    path = fmt / "openexr-images/TestImages/BrightRingsNanInf.exr"
    img, _ = lio.read(path)
    assert (~np.isfinite(img)).sum() == 18  # 18 non-finite values (MANIFEST)
    direct = OpenEXR.File(str(path), separate_channels=True).channels()
    for i, c in enumerate("RGB"):
        np.testing.assert_array_equal(np.isnan(img[..., i]), np.isnan(direct[c].pixels))
        np.testing.assert_array_equal(np.isinf(img[..., i]), np.isinf(direct[c].pixels))


def test_colour_coded_mipmap_reads_level_zero(fmt):
    img, meta = lio.read(fmt / "openexr-images/MultiResolution/ColorCodedLevels.exr")
    assert img.shape == (512, 512, 4)  # level 0 of the 512 x 512 pyramid, not a smaller level
    # level 0 is the neutral one (the smaller levels are tinted): R = G = B everywhere
    np.testing.assert_array_equal(img[..., 0], img[..., 1])
    np.testing.assert_array_equal(img[..., 1], img[..., 2])
    assert np.all(img[..., 3] == 1) and "MIPMAP_LEVELS" in meta["attributes"]["tiles"]
    img, _ = lio.read(fmt / "openexr-images/Tiles/GoldenGate.exr")
    assert img.shape == (860, 1262, 3)  # tiles that do not divide the size


@pytest.mark.parametrize("n", range(1, 17))
def test_display_windows(fmt, n):
    path = fmt / f"openexr-images/DisplayWindow/t{n:02d}.exr"
    img, meta = lio.read(path)
    data, _ = lio.read(path, data_window=True)
    x0, y0, x1, y1 = meta["data_window"]
    X0, Y0, X1, Y1 = meta["display_window"]
    assert img.shape[:2] == (Y1 - Y0 + 1, X1 - X0 + 1) and data.shape[:2] == (y1 - y0 + 1, x1 - x0 + 1)
    expect = np.zeros_like(img)
    for y in range(max(y0, Y0), min(y1, Y1) + 1):  # placement by absolute pixel coordinates
        expect[y - Y0, max(x0, X0) - X0:min(x1, X1) - X0 + 1] = data[y - y0, max(x0, X0) - x0:min(x1, X1) - x0 + 1]
    np.testing.assert_array_equal(img, expect)
    if n in (9, 10, 11, 12):  # display window disjoint from the data: nothing to show
        assert not img.any()
    if n == 13:  # touching by one pixel: the data's last pixel is the display's first
        assert np.argwhere(img.any(-1)).tolist() == [[0, 0]] and (img[0, 0] == data[-1, -1]).all()
    if n == 14:
        assert np.argwhere(img.any(-1)).tolist() == [[100, 100]] and (img[100, 100] == data[0, 0]).all()


def test_overscan_cropped_to_display(fmt):
    path = fmt / "oiio-images/grid-overscan.exr"
    img, meta = lio.read(path)
    full, _ = lio.read(path, data_window=True)
    assert img.shape == (1000, 1000, 4) and full.shape == (1500, 1500, 4)
    np.testing.assert_array_equal(img, full[250:1250, 250:1250])


def test_luminance_chroma_with_chromaticities(fmt):
    rec, meta = lio.read(fmt / "openexr-images/Chromaticities/Rec709_YC.exr")
    xyz, meta_x = lio.read(fmt / "openexr-images/Chromaticities/XYZ_YC.exr")
    assert meta["luminance_chroma"] and meta_x["luminance_chroma"] and meta_x["primaries_converted_to_rec709"]
    assert rec.shape == xyz.shape == (406, 610, 3)
    # the same picture stored with two sets of primaries: after conversion to Rec.709 they agree to
    # half-float and chroma-subsampling error, far closer than without the conversion
    err = np.abs(rec - xyz).mean()
    raw, _ = lio.read(fmt / "openexr-images/Chromaticities/XYZ_YC.exr", rec709=False)
    assert err < 0.002 and np.abs(rec - raw).mean() > 20 * err
    flowers, meta = lio.read(fmt / "openexr-images/LuminanceChroma/Flowers.exr")
    assert flowers.shape == (734, 784, 3) and meta["luminance_chroma"]
    y = flowers @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    assert np.quantile(y, 0.01) >= 0  # a photograph: luminance essentially non-negative


def test_layers_parts_and_odd_channels(fmt):
    base = fmt / "openexr-images"
    fog, meta = lio.read(base / "MultiView/Fog.exr")
    right, meta_r = lio.read(f"{base / 'MultiView/Fog.exr'}:right")
    assert fog.shape == right.shape == (672, 1000, 1) and meta_r["layer"] == "right" and not np.array_equal(fog, right)
    left, _ = lio.read(f"{base / 'MultiView/Adjuster.exr'}:left")
    assert left.shape == (678, 775, 3)
    mp = base / "Beachball/multipart.0001.exr"
    by_name, meta = lio.read(f"{mp}:rgba_right")
    by_index, _ = lio.read(f"{mp}:0")
    single, _ = lio.read(base / "Beachball/singlepart.0001.exr")
    np.testing.assert_array_equal(by_name, by_index)
    np.testing.assert_array_equal(by_name, single)  # the same view, stored both ways
    assert meta["parts"][4] == "rgba_left" and single.shape == (1556, 2048, 4)
    uv, meta = lio.read(f"{mp}:forward_left")
    assert meta["channels"] == ["u", "v"] and uv.shape == (1556, 2048, 2)
    wide, meta = lio.read(base / "TestImages/WideFloatRange.exr")
    assert wide.shape == (500, 500, 1) and meta["channels"] == ["G"] and meta["sample_type"] == "float"


def test_ultrahdr_jpg_reads_its_primary_image(fmt):
    img, meta = lio.read(fmt / "oiio-images/ultrahdr_sky.jpg", raw=True)
    theirs = cv2.imread(str(fmt / "oiio-images/ultrahdr_sky.jpg"), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(np.round(img * 255).astype(np.uint8), theirs[..., ::-1])
