"""``--pixel-type`` acts on every output that can hold it and is refused in one line where the format cannot, for
``lenslab warp`` and ``lenslab convert`` alike: never silently ignored (a PNG, a JPEG, a TIFF's half floats).

Outside values: the sample type of each written file as another library reads it (tifffile for TIFF, OpenCV's
``IMREAD_UNCHANGED`` for PNG, JPEG and PPM/PGM, Pillow's mode for PNG and JPEG, OpenImageIO's channel format for
EXR and PFM, the Radiance header's FORMAT line for RGBE)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write
from lenslab.io.registry import formats

#: what each --pixel-type is, as NumPy names the samples other readers give
DTYPES = {"uint8": np.uint8, "uint16": np.uint16, "half": np.float16, "float": np.float32}


def _source(tmp_path, grey=False):
    y, x = np.mgrid[0:32, 0:64].astype(np.float32)
    img = np.stack([x / 64, y / 32, (x + y) / 96], axis=-1)
    path = tmp_path / ("grey.exr" if grey else "src.exr")
    write(path, img[..., :1] if grey else img, pixel_type="float")
    return path


def _samples(path):
    """The sample type of the file at ``path`` as a library other than lenslab reads it."""
    ext = path.suffix.lower()
    if ext in (".tif", ".tiff"):
        import tifffile

        return np.dtype(tifffile.imread(path).dtype)
    if ext in (".png", ".jpg", ".jpeg", ".ppm", ".pgm", ".pnm"):
        import cv2

        return np.dtype(cv2.imread(str(path), cv2.IMREAD_UNCHANGED).dtype)
    if ext in (".exr", ".pfm"):
        import OpenImageIO as oiio

        spec = oiio.ImageInput.open(str(path)).spec()
        return {"half": np.dtype(np.float16), "float": np.dtype(np.float32)}[str(spec.format)]
    if ext == ".hdr":
        head = path.read_bytes()[:200]
        assert b"FORMAT=32-bit_rle_rgbe" in head
        return "rgbe"
    raise AssertionError(f"no outside reader for {ext}")


def _written():
    """(format name, extension, pixel type) of every type each written image format declares it holds."""
    return [(f.name, f.extensions[0], t) for f in formats().values() if f.writable and f.kind == "image"
            for t in f.pixel_types]


@pytest.mark.parametrize("command", ["warp", "convert"])
@pytest.mark.parametrize("name,ext,kind", _written(), ids=[f"{n}-{t}" for n, _, t in _written()])
def test_every_type_a_format_holds_is_written_as_asked(tmp_path, command, name, ext, kind):
    src = _source(tmp_path, grey=name == "pgm")
    out = tmp_path / f"out{ext}"
    to = ["--to", "equirect", "--size", "64x32"] if command == "warp" else []
    assert main([command, str(src), "-o", str(out), "--pixel-type", kind, "-q", *to]) == 0
    want = "rgbe" if kind == "rgbe" else np.dtype(DTYPES[kind])
    assert _samples(out) == want


@pytest.mark.parametrize("command", ["warp", "convert"])
def test_a_sixteen_bit_png_is_sixteen_bits_to_pillow(tmp_path, command):
    from PIL import Image

    out = tmp_path / "grey.png"
    to = ["--to", "equirect", "--size", "64x32", "--no-alpha"] if command == "warp" else []  # (grey, no coverage)
    assert main([command, str(_source(tmp_path, grey=True)), "-o", str(out), "--pixel-type", "uint16", "-q",
                 *to]) == 0
    with Image.open(out) as im:
        assert im.mode in ("I;16", "I")  # Pillow's 16-bit grey (the file's IHDR says bit depth 16)
    assert out.read_bytes()[24] == 16  # IHDR bit depth, byte 24 of a PNG (PNG spec, 11.2.2)


REFUSED = [  # (output, --pixel-type, the line's end): PNG holds 8/16-bit integers, JPEG 8, EXR half/float, PFM float
    ("out.png", "half", "PNG holds uint8 or uint16 samples; half samples are written to OpenEXR, TIFF"),
    ("out.png", "float", "PNG holds uint8 or uint16 samples; float samples are written to OpenEXR, PFM, TIFF"),
    ("out.jpg", "uint16", "JPEG holds uint8 samples only; uint16 samples are written to PNG, PPM, PGM, TIFF"),
    ("out.exr", "uint8", "OpenEXR holds half or float samples; uint8 samples are written to JPEG, PNG, PPM, PGM, "
                         "TIFF"),
    ("out.pfm", "half", "PFM holds float samples only; half samples are written to OpenEXR, TIFF"),
]


@pytest.mark.parametrize("command", ["warp", "convert"])
@pytest.mark.parametrize("output,kind,end", REFUSED, ids=[f"{o}-{k}" for o, k, _ in REFUSED])
def test_a_type_the_format_cannot_hold_is_one_usage_error(tmp_path, capsys, command, output, kind, end):
    src = _source(tmp_path)
    to = ["--to", "equirect", "--size", "64x32"] if command == "warp" else []
    capsys.readouterr()
    assert main([command, str(src), "-o", str(tmp_path / output), "--pixel-type", kind, *to]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [f"lenslab {command}: error: --pixel-type {kind}: {end}"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["src.exr"]  # no output, no temporary


def test_convert_refuses_two_depths(tmp_path, capsys):
    assert main(["convert", str(_source(tmp_path)), "-o", str(tmp_path / "o.png"), "--pixel-type", "uint16",
                 "--bits", "8"]) == 2
    assert capsys.readouterr().err.strip().endswith("--pixel-type uint16 and --bits 8 ask for two depths; give one "
                                                    "of them")


def test_a_clip_takes_no_pixel_type(tmp_path, capsys):
    assert main(["convert", str(_source(tmp_path)), "-o", str(tmp_path / "c.mp4"), "--pixel-type", "half"]) == 2
    assert "--pixel-type applies to image outputs" in capsys.readouterr().err
