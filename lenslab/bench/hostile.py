"""A hostile corpus: small files that declare far more than they hold, loop, nest, or lie in a header,
each with the command that must refuse it in one line (exit 1 or 2). Made on the spot (nothing is
stored); ``lenslab bench memory`` measures the peak memory of each command and the tests run each
under an address-space limit.

``cases(folder)`` writes the files into ``folder`` and returns :class:`Case` records; ``{src}`` in a
command is a small valid panorama made alongside, ``{out}`` an output folder that must stay empty.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Case:
    name: str
    #: the hostile file (named in the one-line error)
    file: str
    #: the lenslab arguments; ``{file}``, ``{src}`` and ``{out}`` are filled in
    argv: tuple[str, ...]
    #: the text the error line must hold besides the file's name (a word of its cause)
    cause: str = ""
    #: the file must be named in the message (False for arguments such as tiles=/dev/zero)
    named: bool = True


def _tiff(width: int, height: int, loop: bool = False) -> bytes:
    """A little-endian classic TIFF declaring width x height float RGB in one strip of 4 bytes."""
    entries = [(256, 4, 1, width), (257, 4, 1, height), (258, 3, 1, 32), (259, 3, 1, 1), (262, 3, 1, 2),
               (273, 4, 1, 8), (277, 3, 1, 3), (278, 4, 1, height), (279, 4, 1, 4), (339, 3, 1, 3)]
    ifd = 12
    body = struct.pack("<2sHI", b"II", 42, ifd) + b"\0" * 4
    body += struct.pack("<H", len(entries))
    for tag, typ, count, value in entries:
        body += struct.pack("<HHII", tag, typ, count, value)
    return body + struct.pack("<I", ifd if loop else 0)


def _jpeg(width: int, height: int) -> bytes:
    """A baseline JPEG whose frame header declares width x height with a few bytes of scan."""
    dqt = b"\xff\xdb" + struct.pack(">H", 67) + b"\x00" + bytes([1] * 64)
    sof = b"\xff\xc0" + struct.pack(">HBHHB", 17, 8, height, width, 3) + b"".join(
        bytes([i, 0x11, 0]) for i in (1, 2, 3))
    dht = b"\xff\xc4" + struct.pack(">H", 20) + b"\x00" + bytes([1] + [0] * 15) + b"\x00"
    dht += b"\xff\xc4" + struct.pack(">H", 20) + b"\x10" + bytes([1] + [0] * 15) + b"\x00"
    sos = b"\xff\xda" + struct.pack(">HB", 12, 3) + b"".join(bytes([i, 0]) for i in (1, 2, 3)) + b"\x00\x3f\x00"
    return b"\xff\xd8" + dqt + sof + dht + sos + bytes(64) + b"\xff\xd9"


def _iccp_bomb() -> bytes:
    """A valid 8 x 8 PNG whose iCCP chunk (an ICC profile) inflates to 64 MB from 64 kB."""
    import zlib

    from lenslab.io.colour.png_cicp import png_chunk

    rows = b"".join(b"\0" + bytes(8 * 3) for _ in range(8))
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", 8, 8, 8, 2, 0, 0, 0))
            + png_chunk(b"iCCP", b"bomb\0\0" + zlib.compress(bytes(64 << 20), 9))
            + png_chunk(b"IDAT", zlib.compress(rows)) + png_chunk(b"IEND", b""))


def _exr_window(folder: Path, side: int) -> Path:
    """An EXR holding 8 x 8 pixels in a side x side display window."""
    import numpy as np

    from lenslab.io.exr import write_exr

    p = folder / "window.exr"
    write_exr(p, np.ones((8, 8, 3), np.float32))
    data = bytearray(p.read_bytes())
    key = b"displayWindow\0box2i\0" + struct.pack("<i", 16)
    at = data.index(key) + len(key)
    data[at:at + 16] = struct.pack("<iiii", 0, 0, side - 1, side - 1)
    p.write_bytes(bytes(data))
    return p


def _kalibr_bomb(levels: int = 9) -> str:
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]")
    lines.append("cam0:\n  camera_model: *a%d\n  intrinsics: [1, 1, 1, 1]\n  distortion_model: none\n"
                 "  distortion_coeffs: []\n  resolution: [64, 64]" % (levels - 1))
    return "\n".join(lines) + "\n"


def _opencv_yaml(width="640", height="480", matrix="[1, 0, 2, 0, 1, 2, 0, 0, 1]", rows="3", cols="3") -> str:
    return (f"%YAML:1.0\n---\nimage_width: {width}\nimage_height: {height}\ncamera_matrix: !!opencv-matrix\n"
            f"   rows: {rows}\n   cols: {cols}\n   dt: d\n   data: {matrix}\ndistortion_coefficients: "
            "!!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [0, 0, 0, 0]\n")


def cases(folder) -> list[Case]:
    """Write the hostile corpus into ``folder``; the commands that must refuse each file."""
    import numpy as np

    from lenslab.io.exr import write_exr

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    write_exr(folder / "src.exr", np.full((32, 64, 3), 0.5, np.float32))
    files = {
        "huge.tif": _tiff(20000, 20000),
        "loop.tif": _tiff(64, 64, loop=True),
        "huge.jpg": _jpeg(30000, 17000),
        "huge.png": b"\x89PNG\r\n\x1a\n" + struct.pack(">I4sIIBBBBB", 13, b"IHDR", 20000, 20000, 16, 6, 0, 0, 0)
        + b"\0" * 4 + struct.pack(">I4s", 10, b"IDAT") + bytes(14) + struct.pack(">I4s", 0, b"IEND") + bytes(4),
        "huge.hdr": b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 20000\n" + bytes([1, 1, 1, 1]) * 64,
        "chunk.png": b"\x89PNG\r\n\x1a\n" + struct.pack(">I4sIIBBBBB", 13, b"IHDR", 40, 24, 8, 2, 0, 0, 0)
        + bytes.fromhex("bc3bed44") + struct.pack(">I4s", 0xF878A2BF, b"IEND") + bytes.fromhex("ae426082"),
        "nopart.exr": b"v/1\x01" + struct.pack("<i", 0x1002) + b"\0" + bytes(64),  # multi-part, no header
        "nan.hdr": b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=nan\n\n-Y 1 +X 2\n" + bytes(8),
        "tiny.hdr": b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1e-45\n\n-Y 1 +X 2\n" + bytes(8),
        "nan.pfm": b"PF\n2 1\nnan\n" + bytes(24),
        "huge.pfm": b"PF\n20000 20000\n-1\n" + bytes(64),
        "huge.ppm": b"P6\n20000 20000\n255\n" + bytes(64),
        "bomb.yaml": _kalibr_bomb().encode(),
        "deep.json": ('{"camera_matrix": ' + "[" * 100000 + "]" * 100000 + "}").encode(),
        "inf.yaml": _opencv_yaml(width=".inf", height=".inf").encode(),
        "short.yaml": _opencv_yaml(matrix="[1, 0]").encode(),
        "rows.yaml": _opencv_yaml(rows="1000000000", cols="1000000000").encode(),
        "tag.yaml": b"cam0:\n  camera_model: !!python/object/apply:os.system ['echo hi']\n  intrinsics: [1, 1, 1, 1]\n",
        "dtd.xml": b'<?xml version="1.0"?>\n<!DOCTYPE x [<!ENTITY a "aaaaaaaaaa">]>\n<opencv_storage>'
                   b"<image_width>&a;</image_width></opencv_storage>\n",
        "deep.toml": ("[lens]\nmodel = 'perspective'\nx = " + "[" * 5000 + "]" * 5000 + "\n").encode(),
        "size.toml": b'lens = "perspective:fov=90"\nsize = [512]\n',
        "inf.txt": b"# OCamCalib\n#polynomial cam2world\n2 1 0\n\n2 1 0\n\n0 0\n\n1 0 0\n\ninf inf\n",
        "cameras.txt": b"1 PINHOLE 100000 100000 1000 1000 50000 50000\n",
    }
    files["iccp.png"] = _iccp_bomb()
    for name, data in files.items():
        (folder / name).write_bytes(data)
    window = _exr_window(folder, 20000).name
    src = "{src}"
    warp = ("warp", src, "-o", "{out}/w.exr", "--size", "64x32")
    out = [
        Case("tiff_declares_20000", "huge.tif", ("info", "{file}"), "holds"),
        Case("tiff_page_loop", "loop.tif", ("info", "{file}"), "loop"),
        Case("jpeg_sof_30000x17000", "huge.jpg", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "holds"),
        Case("png_declares_20000", "huge.png", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "holds"),
        # (to PFM: EXR to EXR keeps the 8 x 8 data window, and has nothing to place)
        Case("exr_display_window_20000", window, ("convert", "{file}", "--to", "pfm", "-o", "{out}"), "data window"),
        Case("png_chunk_of_4_gb", "chunk.png", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "declares"),
        Case("exr_multipart_without_parts", "nopart.exr", ("convert", "{file}", "--to", "exr", "-o", "{out}"),
             "no part"),
        Case("png_icc_profile_inflates_to_64_mb", "iccp.png", ("convert", "{file}", "--to", "exr", "-o", "{out}"),
             "inflates"),
        Case("hdr_declares_20000", "huge.hdr", ("info", "{file}"), "holds"),
        Case("hdr_exposure_nan", "nan.hdr", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "EXPOSURE"),
        Case("hdr_exposure_tiny", "tiny.hdr", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "EXPOSURE"),
        Case("pfm_scale_nan", "nan.pfm", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "scale"),
        Case("pfm_declares_20000", "huge.pfm", ("info", "{file}"), "holds"),
        Case("ppm_declares_20000", "huge.ppm", ("info", "{file}"), "bytes"),
        Case("kalibr_alias_bomb", "bomb.yaml", warp[:2] + ("--to", "{file}") + warp[2:], "alias"),
        Case("opencv_json_deep", "deep.json", warp[:2] + ("--to", "{file}") + warp[2:], "deep"),
        Case("opencv_inf_size", "inf.yaml", warp[:2] + ("--to", "{file}") + warp[2:], "image_width"),
        Case("opencv_short_matrix", "short.yaml", warp[:2] + ("--to", "{file}") + warp[2:], "camera_matrix"),
        Case("opencv_huge_rows", "rows.yaml", warp[:2] + ("--to", "{file}") + warp[2:], "camera_matrix"),
        Case("yaml_python_tag", "tag.yaml", warp[:2] + ("--to", "{file}") + warp[2:], "tag"),
        Case("xml_dtd", "dtd.xml", warp[:2] + ("--to", "{file}") + warp[2:], "DTD"),
        Case("toml_deep", "deep.toml", warp[:2] + ("--to", "{file}") + warp[2:], "deep"),
        Case("toml_size_512", "size.toml", warp[:2] + ("--to", "{file}") + warp[2:], "size"),
        Case("ocam_inf_size", "inf.txt", warp[:2] + ("--to", "{file}") + warp[2:], "size"),
        Case("colmap_100000_as_to", "cameras.txt", ("warp", src, "-o", "{out}/w.exr", "--to", "{file}"), "limit"),
        Case("image_dev_zero", "/dev/zero", ("convert", "{file}", "--to", "exr", "-o", "{out}"), "regular file"),
        Case("tiles_dev_zero", "/dev/zero", ("warp", src, "-o", "{out}/w.exr", "--size", "64x64", "--to",
                                             "tiled:2x2,tiles=/dev/zero"), "system path"),
    ]
    from lenslab.bench.bombs import write_bombs

    for name in write_bombs(folder):  # valid flat files under 1 MB that decode to hundreds of MB
        out.append(Case(f"bomb_{name.replace('.', '_').replace('-', '_')}", name,
                        ("convert", "{file}", "--to", "exr", "-o", "{out}"), "decompression bomb"))
    return out
