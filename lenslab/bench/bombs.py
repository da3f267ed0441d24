"""Decompression bombs: valid files under 1 MB of one flat colour that decode to hundreds of MB, one
for each way a registered format compresses (PNG and TIFF Deflate, EXR ZIP, PIZ and DWAA, JPEG,
an H.264 clip, an HEVC HEIC), each written by the format's own library (zlib, tifffile, OpenEXR, OpenCV,
PyAV, pillow-heif) or by its specification's rules. Every one must be refused before its pixels are
decoded (:mod:`lenslab.io.budget`: a file under 1 MiB decodes to at most the larger of 96 MiB and
:data:`lenslab.io.budget.SMALL_RATIO` times its bytes). And the files at the budget's edges, which it
admits: :func:`write_edge` (the largest image any file may decode to) and :func:`write_ratio_edge` (the
largest a file of a given size may decode to, padded to that size).

The builders hand their libraries all-zero arrays (``np.zeros``: pages the kernel maps only when
written), so making the corpus costs a few seconds and little memory.
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

#: formats whose files hold every sample raw (PFM, PPM, PGM, PBM): a file's bytes bound what it decodes
#: to (at most 12 float bytes per byte held, 96 for PBM's bits), so no file under 1 MB can be a bomb
RAW = ("pfm", "ppm", "pgm", "pbm")
#: formats whose best compression stays below :data:`lenslab.io.budget.SMALL_RATIO`: Radiance run
#: lengths code at most 127 pixels of a component in 2 bytes, 4 components, 12 float bytes a pixel
#: (127 * 12 / 8 = 190 float bytes per byte; :func:`flat_hdr` of 3800 x 3800 is 0.93 MB for 173 MB),
#: so the budget admits every such file and bounds what it costs by its bytes
BOUNDED = ("hdr",)


def _png(path: Path, side: int = 8192) -> None:
    """8-bit RGB, every row filter 0 of zeros, one zlib stream fed a row at a time (RFC 2083)."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    comp, row = zlib.compressobj(9), bytes(1 + side * 3)
    idat = b"".join([comp.compress(row) for _ in range(side)] + [comp.flush()])
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, 8, 2, 0, 0, 0))
                     + chunk(b"IDAT", idat) + chunk(b"IEND", b""))


def _tiff(path: Path, side: int = 8192) -> None:
    """8-bit RGB in Deflate tiles, written by tifffile from one tile at a time."""
    import numpy as np
    import tifffile

    tiles = (np.zeros((256, 256, 3), np.uint8) for _ in range((side // 256) ** 2))
    tifffile.imwrite(path, tiles, shape=(side, side, 3), dtype=np.uint8, compression="zlib", tile=(256, 256),
                     photometric="rgb")


def _exr(compression: str):
    def build(path: Path, side: int = 6144) -> None:
        """Half RGB, scanlines, written by OpenEXR."""
        import numpy as np
        import OpenEXR

        header = {"compression": getattr(OpenEXR, f"{compression}_COMPRESSION"), "type": OpenEXR.scanlineimage}
        OpenEXR.File(header, {"RGB": np.zeros((side, side, 3), np.float16)}).write(str(path))

    return build


def _jpeg(path: Path, side: int = 6144) -> None:
    """Baseline JPEG of black, 4:2:0, encoded by OpenCV (libjpeg)."""
    import cv2
    import numpy as np

    ok, data = cv2.imencode(".jpg", np.zeros((side, side, 3), np.uint8))
    path.write_bytes(data.tobytes())


def flat_hdr(path: Path, side: int = 3800) -> None:
    """Radiance run-length scanlines (new style: each of the four components as runs of 127), the
    most compact encoding writers make: 0.93 MB for 3800 x 3800."""
    runs = [127] * (side // 127) + ([side % 127] if side % 127 else [])
    line = bytes([2, 2, side >> 8, side & 255]) + b"".join(bytes([128 + n, 0]) for n in runs) * 4
    path.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (side, side) + line * side)


def _video(path: Path, side: int = 6144) -> None:
    """One black H.264 frame (PyAV, libx264)."""
    import av
    import numpy as np

    with av.open(str(path), "w") as clip:
        stream = clip.add_stream("libx264", rate=24)
        stream.width = stream.height = side
        stream.pix_fmt = "yuv420p"
        stream.options = {"preset": "ultrafast"}
        frame = av.VideoFrame.from_ndarray(np.zeros((side, side, 3), np.uint8), format="rgb24")
        for packet in [*stream.encode(frame), *stream.encode()]:
            clip.mux(packet)


def _heif(path: Path, side: int = 4096) -> None:
    """One black 8-bit HEIC image (pillow-heif, x265 at its fastest preset): 4 kB."""
    import pillow_heif

    pillow_heif.from_bytes("RGB", (side, side), bytes(side * side * 3)).save(
        str(path), quality=50, enc_params={"preset": "ultrafast"})


#: format name -> [(file name, builder, (width, height) it declares)]
BOMBS = {
    "png": [("bomb.png", _png, (8192, 8192))],
    "tiff": [("bomb.tif", _tiff, (8192, 8192))],
    "exr": [(f"bomb-{c.lower()}.exr", _exr(c), (6144, 6144)) for c in ("ZIP", "PIZ", "DWAA")],
    "jpg": [("bomb.jpg", _jpeg, (6144, 6144))],
    "video": [("bomb.mp4", _video, (6144, 6144))],
    "heif": [("bomb.heic", _heif, (4096, 4096))],
}


def edge_size(budget: int | None = None, channels: int = 4) -> tuple[int, int]:
    """(width, height) of the largest 2:1 image of ``channels`` (an equirect panorama, which ``lenslab
    warp`` takes without ``--from``) whose float32 decoding stays within ``budget`` bytes (default
    :data:`lenslab.io.budget.BASE_BYTES`: the largest panorama any file may decode to)."""
    from math import isqrt

    from lenslab.io.budget import BASE_BYTES

    budget = BASE_BYTES if budget is None else budget
    height = max(1, isqrt(budget // (8 * channels)))  # float32: 2 * height * height * channels * 4 bytes
    return 2 * height, height


def write_edge(path) -> Path:
    """A flat 2:1 RGBA half EXR (OpenEXR, ZIP) of :func:`edge_size`: tens of kB that decode to the budget
    :data:`lenslab.io.budget.BASE_BYTES` of float32, the most any small file is allowed."""
    _exr_rgba(Path(path), *edge_size())
    return Path(path)


#: formats of :func:`write_ratio_edge`: {name: (channels decoded, extension)}
EDGE_FORMATS = {"exr": (4, ".exr"), "jpg": (3, ".jpg"), "heif": (3, ".heic")}


def write_ratio_edge(path, file_bytes: int, fmt: str = "exr") -> tuple[int, int]:
    """A file of exactly ``file_bytes`` bytes (a flat image padded with metadata the readers skip: an EXR
    string attribute, JPEG ``COM`` segments, HEIF XMP) that declares the largest 2:1 image the budget
    admits from it (:func:`lenslab.io.budget.allowed`): a flat RGBA half EXR, a flat JPEG (OpenCV) or
    a flat HEIC (pillow-heif). A hostile file at the edge of the rule looks like this. Its (width, height)."""
    from lenslab.io.budget import allowed

    path = Path(path)
    channels = EDGE_FORMATS[fmt][0]
    w, h = edge_size(allowed(file_bytes), channels)
    write = {"exr": _exr_rgba, "jpg": _jpeg_padded, "heif": _heif_padded}[fmt]
    pad = 0
    for _ in range(4):  # each writer adds a few bytes of its own around the padding: found, then taken off
        write(path, w, h, pad)
        pad += file_bytes - path.stat().st_size
        if pad < 0:
            raise ValueError(f"a flat {w} x {h} {fmt} takes more than {file_bytes} bytes")
        if path.stat().st_size == file_bytes:
            break
    assert path.stat().st_size == file_bytes, (path, path.stat().st_size, file_bytes)
    return w, h


def _exr_rgba(path: Path, width: int, height: int, pad: int = 0) -> None:
    import numpy as np
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    if pad:
        header["padding"] = "x" * pad
    OpenEXR.File(header, {"RGBA": np.zeros((height, width, 4), np.float16)}).write(str(path))


def _jpeg_padded(path: Path, width: int, height: int, pad: int = 0) -> None:
    import cv2
    import numpy as np

    ok, data = cv2.imencode(".jpg", np.zeros((height, width, 3), np.uint8))
    data = data.tobytes()
    segments = []
    while pad > 0:
        n = max(min(pad, 65535 + 2) - 4, 0)  # a COM segment: marker, 2-byte length (which counts itself), text
        segments.append(b"\xff\xfe" + (n + 2).to_bytes(2, "big") + b"x" * n)
        pad -= n + 4
    path.write_bytes(data[:2] + b"".join(segments) + data[2:])


def _heif_padded(path: Path, width: int, height: int, pad: int = 0) -> None:
    import pillow_heif

    image = pillow_heif.from_bytes("RGB", (width, height), bytes(width * height * 3))
    if pad:
        image.info["xmp"] = b"<x>" + b" " * pad + b"</x>"
    image.save(str(path), quality=50, enc_params={"preset": "ultrafast"})


def write_bombs(folder) -> dict[str, tuple[int, int]]:
    """Write every bomb into ``folder``; {file name: (width, height)}."""
    folder = Path(folder)
    made = {}
    for entries in BOMBS.values():
        for name, build, size in entries:
            build(folder / name)
            made[name] = size
    return made


__all__ = ["BOMBS", "BOUNDED", "EDGE_FORMATS", "RAW", "edge_size", "flat_hdr", "write_bombs", "write_edge",
           "write_ratio_edge"]
