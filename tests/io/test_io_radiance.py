"""Radiance RGBE .hdr against OpenCV both ways, hand-made files built byte by byte, Radiance's formulas."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import lenslab.io as lio


def _image(h=23, w=61, seed=3):
    rng = np.random.default_rng(seed)
    img = (rng.random((h, w, 3)) ** 3 * 50).astype(np.float32)
    img[:, 5:25] = [0.25, 4.0, 1000.0]  # long runs: the run-length encoder has work to do
    img[3, :] = 0.0
    return img


def _radiance(m, e):
    """Radiance's colr_color (src/common/color.c) transcribed in float64: (m + 0.5) * 2**(e - 136), 0 if e == 0."""
    m = np.asarray(m, np.float64)
    return np.where(np.asarray(e) > 0, (m + 0.5) * np.ldexp(1.0, np.asarray(e, np.int64) - 136), 0.0)


def test_opencv_reads_ours_as_it_reads_its_own(tmp_path):
    img = _image()
    lio.write(tmp_path / "ours.hdr", img)
    cv2.imwrite(str(tmp_path / "cv.hdr"), np.ascontiguousarray(img[..., ::-1]))
    ours = cv2.imread(str(tmp_path / "ours.hdr"), cv2.IMREAD_UNCHANGED)
    theirs = cv2.imread(str(tmp_path / "cv.hdr"), cv2.IMREAD_UNCHANGED)
    assert ours.shape == (23, 61, 3)
    # both encoders are Radiance's setcolr (frexp, truncated mantissas): the same bytes, the same floats
    np.testing.assert_array_equal(ours, theirs)
    # and the stored value is within one mantissa step (largest component / 128) below the float written
    err = img[..., ::-1] - ours
    assert (err >= 0).all() and (err <= img.max(axis=-1, keepdims=True) / 128).all()


@pytest.mark.parametrize("rle", [True, False])
def test_opencv_reads_flat_and_rle(tmp_path, rle):
    img = _image(9, 40)
    lio.write(tmp_path / "a.hdr", img, rle=rle)
    cv2.imwrite(str(tmp_path / "cv.hdr"), np.ascontiguousarray(img[..., ::-1]))
    np.testing.assert_array_equal(cv2.imread(str(tmp_path / "a.hdr"), cv2.IMREAD_UNCHANGED),
                                  cv2.imread(str(tmp_path / "cv.hdr"), cv2.IMREAD_UNCHANGED))


def test_we_read_opencv_files_with_radiances_half_step(tmp_path):
    img = _image()
    cv2.imwrite(str(tmp_path / "cv.hdr"), np.ascontiguousarray(img[..., ::-1]))
    theirs = cv2.imread(str(tmp_path / "cv.hdr"), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    ours, meta = lio.read(tmp_path / "cv.hdr")
    assert meta["format"] == "hdr" and meta["channels"] == ["R", "G", "B"] and not meta["display_encoded"]
    assert ours.shape == img.shape and ours.dtype == np.float32
    # OpenCV (Ward's rgbe.c) decodes m * 2**(e-136), Radiance (m + 0.5) * 2**(e-136): the difference is
    # half a step, the same power of two for the three components of a pixel, 0 where the pixel is black
    diff = ours.astype(np.float64) - theirs
    black = theirs.max(axis=-1) == 0
    assert (diff[black] == 0).all()
    d = diff[~black]
    assert (d == d[:, :1]).all()
    mant, _ = np.frexp(d[:, 0])
    assert (mant == 0.5).all()  # exact powers of two
    assert (d[:, 0] <= theirs[~black].max(axis=-1) / 256).all()  # half a step of a mantissa >= 128


def _header(res: bytes, extra: bytes = b"") -> bytes:
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + extra + b"\n" + res + b"\n"


def test_hand_made_new_and_old_rle(tmp_path):
    # scanline 0, new-style RLE (width 8): R a run of 8 x 128; G 8 literals 0..7; B a run of 4 x 64 then
    # 4 literals 1..4; E a run of 8 x 129
    line0 = bytes([2, 2, 0, 8, 128 + 8, 128, 8, 0, 1, 2, 3, 4, 5, 6, 7, 128 + 4, 64, 4, 1, 2, 3, 4, 128 + 8, 129])
    # scanline 1, flat with an old-style run: one pixel, "1 1 1 3" repeats it 3 times, then 4 more pixels
    line1 = bytes([10, 20, 30, 130, 1, 1, 1, 3] + [200, 100, 50, 120] * 2 + [0, 0, 0, 0, 255, 255, 255, 140])
    path = tmp_path / "hand.hdr"
    path.write_bytes(_header(b"-Y 2 +X 8", b"EXPOSURE=2\nEXPOSURE=0.5\nEXPOSURE=4\nCOLORCORR=1 2 0.5\n")
                     + line0 + line1)
    image, meta = lio.read(path)
    assert image.shape == (2, 8, 3)
    m0 = np.stack([np.full(8, 128), np.arange(8), [64] * 4 + [1, 2, 3, 4]], axis=-1)
    row0 = _radiance(m0, np.full((8, 1), 129))
    m1 = np.array([[10, 20, 30]] * 4 + [[200, 100, 50]] * 2 + [[0, 0, 0], [255, 255, 255]])
    e1 = np.array([130] * 4 + [120] * 2 + [0, 140])[:, None]
    row1 = _radiance(m1, e1)
    expected = np.stack([row0, row1]) / 4.0 / np.array([1, 2, 0.5])  # EXPOSURE 2 * 0.5 * 4, COLORCORR
    np.testing.assert_allclose(image, expected, rtol=1e-6)  # float32 rounding of exact binary fractions
    assert meta["attributes"]["exposure"] == 4.0 and meta["attributes"]["colorcorr"] == [1.0, 2.0, 0.5]


@pytest.mark.parametrize("res", [b"-Y 2 +X 3", b"+Y 2 +X 3", b"-Y 2 -X 3", b"+Y 2 -X 3", b"+X 3 -Y 2",
                                 b"-X 3 +Y 2"])
def test_orientations(tmp_path, res):
    # six flat pixels with mantissa R = 10 * k, E = 129, in file order
    data = b"".join(bytes([10 * k, 0, 0, 129]) for k in range(1, 7))
    path = tmp_path / "o.hdr"
    path.write_bytes(_header(res) + data)
    image, meta = lio.read(path)
    stored = np.arange(1, 7).reshape((3, 2) if res.startswith((b"+X", b"-X")) else (2, 3))
    # the picture as Radiance's resolution convention places it: rows from the top, columns from the left
    want = {b"-Y 2 +X 3": stored, b"+Y 2 +X 3": stored[::-1], b"-Y 2 -X 3": stored[:, ::-1],
            b"+Y 2 -X 3": stored[::-1, ::-1], b"+X 3 -Y 2": stored.T, b"-X 3 +Y 2": stored.T[::-1, ::-1]}[res]
    np.testing.assert_allclose(image[..., 0], _radiance(10 * want, 129), rtol=1e-7)
    assert meta["attributes"]["orientation"] == res.decode().replace(" 2", "").replace(" 3", "")


def test_xyze_truncated_and_bad_headers_are_refused(tmp_path):
    p = tmp_path / "x.hdr"
    p.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x80")
    with pytest.raises(lio.FormatError, match="XYZE.*ra_xyze"):
        lio.read(p)
    p.write_bytes(_header(b"-Y 4 +X 8") + bytes([2, 2, 0, 8, 136, 1]))
    with pytest.raises(lio.FormatError, match="scanline 0 of 4"):
        lio.read(p)
    p.write_bytes(_header(b"-Y 4 +Y 8") + bytes(128))
    with pytest.raises(lio.FormatError, match="resolution line"):
        lio.read(p)


def test_write_header_grey_and_alpha(tmp_path):
    grey = np.linspace(0, 2, 20, dtype=np.float32).reshape(2, 10, 1)
    lio.write(tmp_path / "g.hdr", grey)
    assert (tmp_path / "g.hdr").read_bytes().startswith(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n")
    back = cv2.imread(str(tmp_path / "g.hdr"), cv2.IMREAD_UNCHANGED)
    assert back.shape == (2, 10, 3) and (back[..., 0] == back[..., 1]).all()
    rgba = np.ones((2, 10, 4), np.float32)
    lio.write(tmp_path / "a.hdr", rgba)  # alpha dropped: RGBE holds colour only
    assert lio.read(tmp_path / "a.hdr")[0].shape == (2, 10, 3)


def test_real_panorama_against_opencv(tmp_path, shared_data):
    pano, _ = lio.read(shared_data / "hdri" / "studio.exr")
    crop = np.ascontiguousarray(pano[:64, :256, :3])
    cv2.imwrite(str(tmp_path / "p.hdr"), np.ascontiguousarray(crop[..., ::-1]))
    theirs = cv2.imread(str(tmp_path / "p.hdr"), cv2.IMREAD_UNCHANGED)[..., ::-1]
    ours, _ = lio.read(tmp_path / "p.hdr")
    # Radiance's half step above OpenCV's value: at most the largest component / 256
    assert (np.abs(ours - theirs) <= theirs.max(axis=-1, keepdims=True) / 256 + 1e-30).all()


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra.numpy import arrays  # noqa: E402


@settings(max_examples=40, deadline=None)
@given(arrays(np.float32, (3, 9, 3), elements=st.floats(0, 2.0**100, width=32)), st.booleans())
def test_encoder_matches_opencv_for_any_value(tmp_path_factory, pixels, rle):
    """Any non-negative float32 (denormals to 2**100): the same RGBE bytes as OpenCV's encoder gives."""
    d = tmp_path_factory.mktemp("h")
    lio.write(d / "ours.hdr", pixels, rle=rle)
    cv2.imwrite(str(d / "cv.hdr"), np.ascontiguousarray(pixels[..., ::-1]))
    np.testing.assert_array_equal(cv2.imread(str(d / "ours.hdr"), cv2.IMREAD_UNCHANGED),
                                  cv2.imread(str(d / "cv.hdr"), cv2.IMREAD_UNCHANGED))
