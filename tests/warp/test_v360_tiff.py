"""``lenslab warp --compat v360`` into TIFF writes what ffmpeg's v360 writes on the same command: v360 keeps its
input's pixel format, so an 8-bit RGB PNG gives an 8-bit RGB TIFF, an 8-bit RGBA PNG an 8-bit RGBA one (straight
alpha) and a 16-bit PNG a 16-bit RGB TIFF; the pixels v360 leaves at zero (an equisolid view past its back pole)
are black; and a 16-bit PNG source gives a 16-bit PNG. ffmpeg (Debian's, which CI installs) is run here each
time, and both files are read (TIFF with tifffile, PNG with OpenCV): sample dtype, channel count, the alpha's
ExtraSamples tag and every pixel.

Pixel values: v360 blends the 8-bit codes bilinearly with 14-bit integer weights and drops the fraction (up to
1.05 codes below the exact blend, ``tests/warp/test_v360_ffmpeg.py``); lenslab decodes the PNG's sRGB codes,
blends in linear light and encodes the result again, rounding to the nearest code (0.5). The two blends differ
where neighbouring codes differ: a convex blend of codes in [a, b] moved through sRGB's curve departs from the
blend of the codes by at most the largest departure of a two-point blend of a and b, which the test works out
from every 2x2 block of the source with colour-science's sRGB functions in float64. The tolerance is the sum.
"""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

from lenslab.cli.main import main
from tests.warp.test_v360_ffmpeg import ffmpeg as _ffmpeg  # Debian's ffmpeg, required

tifffile = pytest.importorskip("tifffile")
colour = pytest.importorskip("colour")

#: an equisolid output past its back pole: v360 writes zeros there
FFMPEG_VIEW = "v360=input=e:output=equisolid:h_fov=300:v_fov=300:w=64:h=64:interp=line"
LENSLAB_VIEW = ["--from", "equirect", "--to", "fisheye:fov=300,mapping=equisolid", "--size", "64x64"]


def _source(bits: int, channels: int) -> np.ndarray:
    """A smooth panorama (at most ~8 8-bit codes per pixel) of the given depth and channels."""
    y, x = np.mgrid[0:64, 0:128] + 0.5
    r = 128 + 100 * np.sin(2 * np.pi * x / 128) * np.cos(np.pi * y / 64)
    g = 128 + 90 * np.cos(2 * np.pi * (x / 128 + y / 64))
    b = 40 + 200 * y / 64
    rgb = np.stack([r, g, b], axis=-1) / 255
    if channels == 4:
        rgb = np.dstack([rgb, np.ones((64, 128))])
    top = (1 << bits) - 1
    return np.round(rgb * top).astype(np.uint8 if bits == 8 else np.uint16)


def _write_png(path, pixels: np.ndarray) -> None:
    import cv2

    order = [2, 1, 0, 3][:pixels.shape[2]]  # OpenCV writes BGR(A)
    assert cv2.imwrite(str(path), pixels[..., order])


def _blend_departure(codes: np.ndarray, top: int) -> float:
    """The largest gap, in codes, between a blend of two codes a <= b and the same blend done on their sRGB-decoded
    values and encoded again, over the extremes (a, b) of every 2x2 block of ``codes`` (colour channels)."""
    c = codes[..., :3].astype(np.float64)
    blocks = np.stack([c[:-1, :-1], c[:-1, 1:], c[1:, :-1], c[1:, 1:]])
    a, b = blocks.min(axis=0).ravel(), blocks.max(axis=0).ravel()
    t = np.linspace(0, 1, 65)[:, None]
    linear = (1 - t) * colour.models.eotf_sRGB(a / top) + t * colour.models.eotf_sRGB(b / top)
    return float(np.abs(colour.models.eotf_inverse_sRGB(linear) * top - ((1 - t) * a + t * b)).max())


@pytest.mark.parametrize("bits, channels", [(8, 3), (8, 4), (16, 3)], ids=["8-bit RGB", "8-bit RGBA", "16-bit RGB"])
def test_compat_v360_tiff_is_ffmpegs_tiff(tmp_path, bits, channels):
    codes = _source(bits, channels)
    ff, ll = _both(tmp_path, codes, "tiff")
    with tifffile.TiffFile(tmp_path / "ffmpeg.tiff") as a, tifffile.TiffFile(tmp_path / "lenslab.tiff") as b:
        assert [int(v) for v in b.pages[0].extrasamples] == [int(v) for v in a.pages[0].extrasamples]
    _same(ff, ll, codes, bits, channels)


def test_compat_v360_png_from_a_16_bit_png_is_16_bit_as_ffmpegs(tmp_path):
    import cv2

    codes = _source(16, 3)
    ff, ll = _both(tmp_path, codes, "png", read=lambda p: cv2.imread(str(p), cv2.IMREAD_UNCHANGED)[..., ::-1])
    assert ff.dtype == ll.dtype == np.uint16  # ffmpeg keeps the 16-bit source's depth, and so does lenslab
    _same(ff, ll, codes, 16, 3)


def _both(tmp_path, codes: np.ndarray, ext: str, read=None) -> tuple[np.ndarray, np.ndarray]:
    """ffmpeg's and lenslab's outputs of the view from a PNG of ``codes``, as their files hold them."""
    src, theirs, ours = tmp_path / "pano.png", tmp_path / f"ffmpeg.{ext}", tmp_path / f"lenslab.{ext}"
    _write_png(src, codes)
    subprocess.run([_ffmpeg(), "-v", "error", "-y", "-i", str(src), "-vf", FFMPEG_VIEW, str(theirs)], check=True)
    assert main(["warp", str(src), *LENSLAB_VIEW, "--compat", "v360", "-o", str(ours), "-q"]) == 0
    read = read or tifffile.imread
    return read(theirs), read(ours)


def _same(ff: np.ndarray, ll: np.ndarray, codes: np.ndarray, bits: int, channels: int) -> None:
    # what v360 does, read from its file: the source's depth and channels
    assert ff.dtype == (np.uint8 if bits == 8 else np.uint16) and ff.shape == (64, 64, channels)
    assert ll.dtype == ff.dtype and ll.shape == ff.shape
    zeros = (ff == 0).all(axis=-1)
    assert zeros.sum() > 400  # the view has pixels past the back pole: black (RGBA: transparent black) in both
    assert (ll[zeros] == 0).all()
    top = (1 << bits) - 1
    # v360's truncation (1.05 codes of the file's own depth), lenslab's rounding (0.5), the two blends' departure
    # (8-bit: 0.26 codes, 16-bit: 63), v360's float32 map (0.01 8-bit codes at the source's steepest 8 codes/px)
    tol = 1.05 + 0.5 + _blend_departure(codes, top) + 0.01 * top / 255
    diff = np.abs(ll[~zeros].astype(np.float64) - ff[~zeros])
    assert diff[..., :3].max() <= tol, (diff.max(), tol)
    if channels == 4:
        assert (ll[~zeros][:, 3] == ff[~zeros][:, 3]).all()  # opaque wherever v360 drew from the source


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
