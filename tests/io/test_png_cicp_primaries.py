"""A PQ display on P3-D65 primaries says so in its PNG (cICP colour primaries 12, SMPTE EG 432-1, ITU-T H.273
table 2), and PNGs and clips tagged P3-D65 are read into Rec.709 by colour-science's P3-D65 -> BT.709 matrix.

Expected values: H.273's code points written out here, the chunk bytes parsed here (PNG Specification,
5.3), PyOpenColorIO's processor for the display, and colour-science's ST 2084 EOTF and RGB matrices in
float64."""

from __future__ import annotations

import struct
import subprocess
import sys
import zlib
from fractions import Fraction

import cv2
import numpy as np
import pytest

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")
colour = pytest.importorskip("colour")

import lenslab.io as lio  # noqa: E402

P3_TO_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["P3-D65"], colour.RGB_COLOURSPACES["ITU-R BT.709"])
# H.273: colour primaries 9 BT.2020, 12 SMPTE EG 432-1 (P3-D65); transfer 16 ST 2084, 18 ARIB STD-B67; matrix 0
# identity (RGB); full range 1
H273 = {"ST2084-P3-D65 - Display": (12, 16, 0, 1), "Rec.2100-PQ - Display": (9, 16, 0, 1),
        "Rec.2100-HLG - Display": (9, 18, 0, 1)}


def _chunks(data: bytes):
    pos = 8
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        yield kind, data[pos + 8:pos + 8 + n]
        pos += 12 + n


def _png_with_cicp(path, codes16: np.ndarray, points) -> None:
    ok, buf = cv2.imencode(".png", cv2.cvtColor(codes16, cv2.COLOR_RGB2BGR))
    assert ok
    png = buf.tobytes()
    body = b"cICP" + bytes(points)
    chunk = struct.pack(">I", 4) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)
    path.write_bytes(png[:33] + chunk + png[33:])  # after the signature (8) and IHDR (25 bytes)


@pytest.mark.parametrize("display", sorted(H273))
def test_display_code_points_are_h273s(display):
    from lenslab.io.colour.png_cicp import display_code_points

    assert display_code_points(display) == H273[display]


def test_a_p3_pq_png_is_tagged_p3_and_holds_opencolorios_codes(tmp_path):
    img = np.array([[[0.18, 0.18, 0.18], [1.0, 0.2, 0.05], [0.1, 0.6, 0.2]]], np.float32)
    lio.write(tmp_path / "s.exr", img, pixel_type="float")
    out = tmp_path / "p3.png"
    display = "ST2084-P3-D65 - Display"
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "s.exr"), "--to", "png",
                          "--display", display, "--view", "Un-tone-mapped", "-o", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    chunks = list(_chunks(out.read_bytes()))
    cicp = [data for kind, data in chunks if kind == b"cICP"]
    assert cicp == [bytes(H273[display])]
    kinds = [kind for kind, _ in chunks]
    assert kinds.index(b"cICP") < kinds.index(b"IDAT")
    # the codes are OpenColorIO's for this display (with 1.0 put at 203 cd/m2: a colorimetric view)
    back, _ = lio.read(out)
    codes = cv2.cvtColor(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), cv2.COLOR_BGR2RGB).astype(np.float64) / 65535
    light = colour.models.eotf_ST2084(codes) / 203.0 @ P3_TO_709.T  # P3-D65 display light -> Rec.709, 1.0 = 203
    np.testing.assert_allclose(back, light, rtol=2e-3, atol=1e-5)  # 16-bit PQ codes: < 0.03 % a step, + float32
    np.testing.assert_allclose(back, img, rtol=2e-3, atol=2e-4)  # and the scene it was made of comes back


def test_a_png_tagged_p3_pq_is_read_into_rec709(tmp_path):
    rng = np.random.default_rng(7)
    codes = rng.integers(0, 65536, size=(5, 7, 3), dtype=np.uint16)
    _png_with_cicp(tmp_path / "p3.png", codes, (12, 16, 0, 1))
    got, _ = lio.read(tmp_path / "p3.png")
    want = colour.models.eotf_ST2084(codes / 65535.0) / 203.0 @ P3_TO_709.T
    np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-7)  # float32 of the float64 formula


def test_a_clip_tagged_p3_is_converted_by_colour_sciences_matrix():
    from lenslab.io.video import VideoInfo, to_linear

    codes = np.linspace(0.0, 1.0, 12).reshape(1, 4, 3)
    info = VideoInfo(4, 1, Fraction(24), 1, "h265", "yuv420p10le", primaries=12, transfer=16, matrix=9, range=1)
    want = colour.models.eotf_ST2084(codes) / 203.0 @ P3_TO_709.T
    np.testing.assert_allclose(to_linear(codes, info), want, rtol=1e-6, atol=1e-9)
