"""Measure what the input budget's ratio R (lenslab.io.budget.SMALL_RATIO) must lie between: the decoded
float bytes per file byte of genuine images, and of the flattest files each format makes.

    python tools/budget_ratios.py [--hdri ../shared/data/hdri] [--formats ../shared/data/formats]
                                  [--views 3] [--json out.json]

Genuine: perspective views (70 degrees across, a phone's main camera) of 256 x 192 to 4000 x 3000 (see
:data:`SIZES`) warped by ``lenslab warp`` from every panorama in --hdri (exposure auto, the default tone
curve, 8-bit PNG), saved as JPEG at qualities 70 to 95 (Pillow's libjpeg, 4:2:0 as phones write), PNG
(Pillow, zlib level 6) and HEIC (pillow-heif at its default quality); the same views with the noise of a
phone sensor (Gaussian, 1.5 code values); and every file under --formats (those named bad-* or bomb-*
are counted as hostile). Hostile: flat-colour 4032 x 3024 files of every format that compresses, each at
the settings that make it smallest. The ratio is the budget's own view of a file:
``Declared.float_bytes`` from the format's ``declare`` hook over the file's bytes. One run with
``--views 3`` takes about 5 minutes of CPU.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

W, H = 4032, 3024  # a 12-megapixel phone photo
#: the panoramas and format files beside the repository (../shared/data)
DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def ratio(path: Path, header: int = 0) -> float:
    """Declared float bytes over the file's bytes (less ``header``, the bytes any file of its encoding holds)."""
    from lenslab.io.registry import get, sniff

    declared = get(sniff(path)).declare(path)
    return declared.float_bytes / (path.stat().st_size - header)


def _encodings(img, folder: Path, stem: str) -> dict[str, Path]:
    """``img`` (8-bit RGB) saved the ways a camera or a user saves a photo."""
    import pillow_heif
    from PIL import Image

    pil = Image.fromarray(img)
    out = {}
    for q in (70, 80, 90, 95):
        out[f"jpeg q{q}"] = folder / f"{stem}-q{q}.jpg"
        pil.save(out[f"jpeg q{q}"], quality=q)
    out["png"] = folder / f"{stem}.png"
    pil.save(out["png"])
    out["heic"] = folder / f"{stem}.heic"
    pillow_heif.from_pillow(pil).save(str(out["heic"]))
    return out


#: (width, height) of the views; a 70-degree view of a 1024-wide panorama spans 199 of its pixels, so
#: these magnify it 1.3, 2.6, 5.1 and 20 times (a 12 MP view is 20 times softer than the panorama)
SIZES = ((256, 192), (512, 384), (1024, 768), (4000, 3000))


def _headers(folder: Path) -> dict[str, int]:
    """The bytes each encoding spends on a 16 x 16 flat image: its headers and tables, subtracted from a
    small view's file so that its ratio is that of its pixels, as in a 12 MP file."""
    import numpy as np

    made = _encodings(np.full((16, 16, 3), 128, np.uint8), folder, "header")
    return {what: path.stat().st_size for what, path in made.items()}


def genuine(hdri: Path, folder: Path, views: int) -> dict[str, list[float]]:
    import numpy as np
    from PIL import Image

    headers = _headers(folder)
    found: dict[str, list[float]] = {}
    for pano in sorted(hdri.glob("*.exr")):
        for w, h in SIZES:
            for v in range(views if w < 4000 else 1):
                view = folder / f"view-{pano.stem}-{v}.png"
                subprocess.run([sys.executable, "-m", "lenslab", "warp", str(pano), "-o", str(view), "--to",
                                "perspective:fov=70", "--size", f"{w}x{h}", "--yaw", str(360 * v // views),
                                "--exposure", "auto", "--no-alpha", "-q", "--overwrite"], check=True,
                               stderr=subprocess.DEVNULL)
                img = np.asarray(Image.open(view).convert("RGB"))
                noisy = np.clip(img + np.random.default_rng(v).normal(0, 1.5, img.shape), 0, 255).astype(np.uint8)
                for kind, pixels in (("", img), ("noisy ", noisy)):
                    for what, path in _encodings(pixels, folder, f"{pano.stem}-{v}{kind.strip()}").items():
                        found.setdefault(f"{w}x{h} {kind}{what}", []).append(
                            ratio(path, headers[what] if w < 4000 else 0))
                        path.unlink()
                view.unlink()
    return found


def dataset(formats: Path) -> tuple[dict[str, list[float]], dict[str, float]]:
    """The ratios of the files under ``formats``: ({"data .ext": [ratio...]}, {name: ratio} of the hostile
    ones, named bad-* or bomb-* by the corpus)."""
    from lenslab.errors import FormatError

    found: dict[str, list[float]] = {}
    bad: dict[str, float] = {}
    for path in sorted(p for p in formats.rglob("*") if p.is_file()):
        try:
            r = ratio(path)
        except (FormatError, AttributeError, TypeError):
            continue  # not an image lenslab reads, or one without a declare hook
        if path.name.startswith(("bad", "bomb")):
            bad[f"data {path.name}"] = r
        else:
            found.setdefault(f"data {path.suffix.lower()}", []).append(r)
    return found, bad


def hostile(folder: Path) -> dict[str, float]:
    import cv2
    import numpy as np
    import OpenEXR
    import pillow_heif
    import tifffile
    from PIL import Image

    colour = np.zeros((H, W, 3), np.uint8) + np.array([200, 120, 60], np.uint8)
    pil = Image.fromarray(colour)
    made = {}
    jpegs = {"jpeg baseline q75 4:2:0": {}, "jpeg baseline 4:4:4": {"subsampling": 0},
             "jpeg optimized 4:2:0": {"optimize": True}, "jpeg progressive 4:2:0": {"progressive": True},
             "jpeg progressive optimized 4:2:0": {"progressive": True, "optimize": True}}
    for name, opts in jpegs.items():
        made[name] = folder / f"{len(made)}.jpg"
        pil.save(made[name], **opts)
    made["jpeg opencv"] = folder / "cv.jpg"
    cv2.imwrite(str(made["jpeg opencv"]), colour)
    made["png level 9"] = folder / "flat.png"
    pil.save(made["png level 9"], compress_level=9)
    made["png grey level 9"] = folder / "grey.png"
    pil.convert("L").save(made["png grey level 9"], compress_level=9)
    for q in (50, 90):
        made[f"heic q{q}"] = folder / f"flat{q}.heic"
        pillow_heif.from_pillow(pil).save(str(made[f"heic q{q}"]), quality=q)
    made["heic default"] = folder / "flat.heic"
    pillow_heif.from_pillow(pil).save(str(made["heic default"]))
    for c in ("ZIP", "PIZ", "DWAA", "RLE", "PXR24"):
        made[f"exr half {c}"] = folder / f"flat-{c}.exr"
        header = {"compression": getattr(OpenEXR, f"{c}_COMPRESSION"), "type": OpenEXR.scanlineimage}
        OpenEXR.File(header, {"RGB": np.full((H, W, 3), 0.5, np.float16)}).write(str(made[f"exr half {c}"]))
    for c in ("zlib", "lzw"):
        made[f"tiff 8-bit {c}"] = folder / f"flat-{c}.tif"
        tifffile.imwrite(made[f"tiff 8-bit {c}"], colour, compression=c, photometric="rgb")
    made["hdr rle"] = folder / "flat.hdr"
    cv2.imwrite(str(made["hdr rle"]), np.full((H, W, 3), 0.5, np.float32))
    return {name: ratio(path) for name, path in made.items()}


def build_parser() -> argparse.ArgumentParser:
    from lenslab.jobs.arguments import ArgumentParser  # one-line errors, no abbreviated options

    parser = ArgumentParser(prog="python tools/budget_ratios.py", description=__doc__.splitlines()[0])
    parser.add_argument("--hdri", type=Path, default=DATA / "hdri")
    parser.add_argument("--formats", type=Path, default=DATA / "formats")
    parser.add_argument("--views", type=int, default=3, help="views per panorama (yaws spread evenly; 0: none)")
    parser.add_argument("--json", type=Path)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="lenslab-ratios-") as d:
        data, bad = dataset(args.formats)
        found = {**(genuine(args.hdri, Path(d), args.views) if args.views else {}), **data}
        flat = {**hostile(Path(d)), **bad}
    print("genuine images: decoded float bytes / file bytes (min, median, max; count)")
    for name, rs in found.items():
        rs = sorted(rs)
        print(f"  {name:28s} {rs[0]:8.1f} {rs[len(rs) // 2]:8.1f} {rs[-1]:8.1f}   ({len(rs)})")
    print("flat-colour 4032 x 3024 files, and the corpus's hostile files: decoded float bytes / file bytes")
    for name, r in sorted(flat.items(), key=lambda kv: kv[1]):
        print(f"  {name:34s} {r:10.1f}")
    if args.json:
        args.json.write_text(json.dumps({"genuine": found, "flat": flat}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
