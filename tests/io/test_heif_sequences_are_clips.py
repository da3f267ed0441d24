"""A HEIF image sequence (``.heics``: an ISO base media file whose ``ftyp`` names a sequence brand, ``msf1`` or
``hevc``, and no image brand) holds a track of frames and no still image: it is read as the clip it is, as
FFmpeg reads it, not refused as a damaged HEIF. A file that names an image brand (``mif1``, ``heic``) beside
a sequence brand holds a still image too, and is read as HEIF.

Brands: ISO/IEC 23008-12 (``mif1``/``msf1``, ``heic``/``hevc``), written byte by byte here as ISO/IEC
14496-12 lays out ``ftyp``. The clip: HEVC frames written by PyAV (FFmpeg's mp4 muxer, its ``brand`` option),
its track's handler made ``pict`` (an image sequence's, ISO/IEC 23008-12 7.2); expected values are the
width, height and frame count FFmpeg (through PyAV) decodes from it.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io.registry import sniff, sniff_bytes

FRAMES = 4


def _ftyp(major: bytes, *compatible: bytes) -> bytes:
    body = major + b"\x00\x00\x00\x00" + b"".join(compatible)
    return (struct.pack(">I", 8 + len(body)) + b"ftyp" + body + bytes(32))[:32]


@pytest.mark.parametrize("major,compatible", [(b"msf1", (b"msf1", b"iso8")), (b"msf1", (b"msf1", b"hevc")),
                                              (b"hevc", (b"msf1", b"hevc")), (b"hevx", (b"msf1", b"hevx"))])
def test_a_sequence_brand_without_an_image_brand_is_a_clip(major, compatible):
    assert sniff_bytes(_ftyp(major, *compatible)) == "video"


@pytest.mark.parametrize("major,compatible", [(b"msf1", (b"mif1", b"msf1", b"heic")), (b"hevc", (b"heic", b"hevc")),
                                              (b"heic", (b"mif1", b"heic", b"msf1")), (b"mif1", (b"mif1",))])
def test_an_image_brand_makes_it_heif(major, compatible):
    assert sniff_bytes(_ftyp(major, *compatible)) == "heif"


def test_a_heif_image_sequence_converts_as_a_clip(tmp_path, capsys):
    av = pytest.importorskip("av")
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")
    path = tmp_path / "burst.heics"
    with av.open(str(path), "w", format="mp4", options={"brand": "msf1"}) as out:
        stream = out.add_stream("libx265", rate=5)
        stream.width, stream.height, stream.pix_fmt = 64, 48, "yuv420p"
        stream.options = {"x265-params": "log-level=none"}
        for i in range(FRAMES):
            codes = np.random.default_rng(i).integers(0, 256, (48, 64, 3), dtype=np.uint8)
            out.mux(stream.encode(av.VideoFrame.from_ndarray(codes, format="rgb24")))
        out.mux(stream.encode())
    data = bytearray(path.read_bytes())
    hdlr = data.find(b"hdlr")
    assert data[hdlr + 12:hdlr + 16] == b"vide"
    data[hdlr + 12:hdlr + 16] = b"pict"  # an image sequence's track
    path.write_bytes(bytes(data))
    assert data[8:12] == b"msf1" and b"mif1" not in data[:64]
    with av.open(str(path)) as clip:
        frames = list(clip.decode(video=0))
    assert (frames[0].width, frames[0].height, len(frames)) == (64, 48, FRAMES)

    assert sniff(path) == "video"
    assert main(["convert", str(path), "-o", str(tmp_path / "frames"), "--to", "png", "-q"]) == 0, \
        capsys.readouterr().err
    written = sorted((tmp_path / "frames").iterdir())
    assert len(written) == FRAMES
    import lenslab.io as lio

    assert lio.read(written[0])[0].shape[:2] == (48, 64)
