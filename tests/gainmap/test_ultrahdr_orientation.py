"""An Ultra HDR JPEG whose base image records EXIF orientation 6 (a portrait phone photo) reads as its HDR rendition
turned as the photo is shown: the gain map applied in the frame it was coded in (the base's stored one), then the
whole image turned 90 degrees clockwise, as OpenCV's ``cv2.rotate`` turns the same file read without the tag. A
gain map applied after turning the base would sample the wrong places (the gain here varies along the rows)."""

from __future__ import annotations

import io

import cv2
import numpy as np
from PIL import Image

import lenslab
from tests.gainmap.files import jpeg, ultrahdr


def _base(orientation: int | None) -> bytes:
    codes = np.kron(np.random.default_rng(3).integers(40, 220, (4, 6, 3)), np.ones((8, 8, 1))).astype(np.uint8)
    if orientation is None:
        return jpeg(codes)
    exif = Image.Exif()
    exif[0x0112] = orientation
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "JPEG", quality=100, subsampling=0, exif=exif.tobytes())
    return buf.getvalue()


def test_the_hdr_rendition_is_turned_as_shown(tmp_path):
    gain = np.tile(np.linspace(0, 255, 12), (8, 1)).astype(np.uint8)  # 12 x 8: a quarter of 48 x 32
    meta = {"GainMapMin": 0, "GainMapMax": 2, "HDRCapacityMin": 0, "HDRCapacityMax": 2}
    plain, turned = tmp_path / "plain.jpg", tmp_path / "turned.jpg"
    plain.write_bytes(ultrahdr(_base(None), jpeg(gain), meta))
    turned.write_bytes(ultrahdr(_base(6), jpeg(gain), meta))
    stored, _ = lenslab.read(plain)
    shown, meta_read = lenslab.read(turned)
    assert stored.max() > 1.5  # the HDR rendition, not the SDR base
    assert "EXIF orientation 6" in meta_read["attributes"]["orientation"]
    np.testing.assert_array_equal(shown, cv2.rotate(stored, cv2.ROTATE_90_CLOCKWISE))
