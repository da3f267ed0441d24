"""Every registered image format honours what its record declares, checked against OpenImageIO.

Parametrized from the format registry (:func:`lenslab.io.registry.formats`): a new format plugin is
tested with no edit here. For each writable image format, each declared channel count and bit depth:
the file lenslab writes reads back with those channels, that bit depth, a declared sample type and the
declared encoding (linear for HDR formats, display-encoded otherwise); OpenImageIO (an outside reader)
reads the same stored values from it; a format that declares a camera keeps one, the others refuse it.
"""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.errors import FormatError
from lenslab.io.registry import formats
from lenslab.lenses import Camera, make_lens

oiio = pytest.importorskip("OpenImageIO")

IMAGE_FORMATS = [f for f in formats().values() if f.kind == "image" and f.readable and f.writable]
CASES = [(f.name, c, b) for f in IMAGE_FORMATS for c in f.channels
         for b in (f.bit_depths if "bits" in f.write_options else (None,))]
#: how closely OpenImageIO's reading must match lenslab's, per stored sample: both decode the same
#: stored numbers (integer codes over maxval, or half/float values), so only float32 rounding differs
OIIO_TOL = 1e-6


def opaque(c: int, seed: int = 0) -> np.ndarray:
    """An image with every pixel different and alpha (if any) 1, so stored colour is the same whether a
    format keeps it premultiplied (EXR) or straight (PNG, TIFF)."""
    img = np.random.default_rng(seed).random((9, 13, c)).astype(np.float32)
    if c in (2, 4):
        img[..., -1] = 1.0
    return img


def outside_pixels(name: str, path) -> np.ndarray:
    """The file's samples as an outside reader gives them: OpenImageIO, but OpenCV for PFM (OpenImageIO
    reads PFM rows top to bottom; the format stores them bottom to top, as OpenCV reads them)."""
    if name == "pfm":
        import cv2

        img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        return (img[..., ::-1] if img.ndim == 3 else img[..., None]).astype(np.float32)
    return oiio_pixels(path)


def oiio_pixels(path) -> np.ndarray:
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    try:
        spec = inp.spec()
        return np.asarray(inp.read_image("float"), dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    finally:
        inp.close()


@pytest.mark.parametrize("name,channels,bits", CASES, ids=[f"{n}-{c}ch-{b or 'default'}" for n, c, b in CASES])
def test_format_honours_its_declaration(tmp_path, name, channels, bits):
    fmt = formats()[name]
    options = {"bits": bits} if bits else {}
    path = lio.write(tmp_path / f"x{fmt.extensions[0]}", opaque(channels), **options)
    back, meta = lio.read(path)
    stored = channels  # what the record declares is what the file holds and what reads back
    assert back.dtype == np.float32 and back.shape == (9, 13, stored)
    assert len(meta["channels"]) == stored and stored in fmt.channels
    assert meta["bit_depth"] in fmt.bit_depths and (bits is None or meta["bit_depth"] == bits)
    assert meta["sample_type"] in fmt.sample_types
    assert meta["display_encoded"] is (not fmt.hdr)
    # the stored samples, as OpenImageIO reads them: codes over maxval (raw) for display-encoded files
    if "raw" in fmt.read_options:
        back, _ = lio.read(path, raw=True)
    theirs = outside_pixels(name, path)
    assert theirs.shape[-1] == stored
    np.testing.assert_array_less(np.abs(back - theirs), tolerance(fmt.name, theirs))


def tolerance(name: str, theirs: np.ndarray) -> np.ndarray:
    """Per-sample bound on |lenslab - OpenImageIO|. Lossless files: float32 rounding only. RGBE: readers
    differ on where in a mantissa step a value lies (Ward's +0.5 or not), up to one step of the shared
    exponent, 1/128 of the brightest channel at the least. JPEG: two IDCT implementations round apart by
    up to one code."""
    if name == "hdr":
        return np.max(np.abs(theirs), axis=-1, keepdims=True) / 128.0 + 1e-7 + 0 * theirs
    if name == "jpg":
        return np.full(theirs.shape, 1.0 / 255 + 1e-6)
    return np.full(theirs.shape, OIIO_TOL)


@pytest.mark.parametrize("name", [f.name for f in IMAGE_FORMATS])
def test_alpha_is_kept_where_declared(tmp_path, name):
    fmt = formats()[name]
    if not fmt.alpha:
        assert not any(c in (2, 4) for c in fmt.channels)
        return
    img = opaque(4 if 4 in fmt.channels else 2, seed=1)
    img[..., -1] = np.linspace(0.25, 1.0, img.shape[1], dtype=np.float32)[None, :]
    img[..., :-1] *= img[..., -1:]  # premultiplied, as in memory
    back, _ = lio.read(lio.write(tmp_path / f"a{fmt.extensions[0]}", img))
    # 8-bit alpha is one code in 255; half floats keep 11 bits
    np.testing.assert_allclose(back[..., -1], img[..., -1], atol=0.5 / 255 + 1e-6)


@pytest.mark.parametrize("name", [f.name for f in IMAGE_FORMATS])
def test_camera_is_kept_where_declared_and_refused_elsewhere(tmp_path, name):
    fmt = formats()[name]
    c = 3 if 3 in fmt.channels else fmt.channels[0]
    cam = Camera(make_lens("fisheye:fov=190,mapping=equisolid", (13, 9)))
    target = tmp_path / f"c{fmt.extensions[0]}"
    if not fmt.camera:
        with pytest.raises(FormatError):
            lio.write(target, opaque(c), camera=cam)
        return
    _, meta = lio.read(lio.write(target, opaque(c), camera=cam))
    assert meta["camera"].lens == cam.lens
