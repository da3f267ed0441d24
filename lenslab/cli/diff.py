"""Compare two images: mean, RMS and max error (absolute and relative, per channel), PSNR, FLIP and the
share of pixels over a threshold, with OpenImageIO idiff's thresholds and exit codes.

Values are compared as lenslab reads them: linear light (8- and 16-bit files are decoded from sRGB),
premultiplied by alpha. Where either image has alpha, only pixels fully covered in both are compared
(their colour channels); --no-mask compares every pixel and channel, alpha included, as idiff does.
Mean, RMS and max error, PSNR and the pixel counts over --warn/--fail are those of OpenImageIO's
ImageBufAlgo.compare (idiff, oiiotool --diff); relative error is |a - b| / ((|a| + |b|) / 2).
FLIP is NVIDIA's perceptual difference: HDR-FLIP when either image goes above 1, else LDR-FLIP.

exit codes (idiff's): 0 PASS, 1 WARNING (over --warn), 2 FAILURE (over --fail; also a usage error),
3 the images differ in size or channels, 4 an input cannot be read or the error map cannot be written.

examples:
  lenslab diff render.exr warped.exr
  lenslab diff ref.exr test.exr --fail 0.01 --fail-percent 0.5 --warn 0.001 -o error.exr
  lenslab diff a.png b.png --json > report.json
"""

from __future__ import annotations

import argparse
import math
import os
import sys

from lenslab.jobs.arguments import positive_float
from lenslab.jobs.diff_arguments import add_threshold_arguments, thresholds_from

EXIT_DIFFERENT_SIZE, EXIT_FILE = 3, 4


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("first", metavar="A", help="the reference image")
    parser.add_argument("second", metavar="B", help="the image to compare with it (a folder: the file of A's name in it)")
    add_threshold_arguments(parser)
    parser.add_argument("--no-mask", action="store_true",
                        help="compare every pixel and channel, alpha included (default: only pixels fully "
                             "covered in both images, colour channels)")
    parser.add_argument("--flip", choices=("auto", "hdr", "ldr", "off"), default="auto",
                        help="FLIP: HDR above 1, else LDR (auto), or as chosen; off skips it (faster)")
    parser.add_argument("-o", "--output", metavar="FILE",
                        help="write the error map |A - B| per channel (alpha: 1 where compared)")
    parser.add_argument("--signed", action="store_true", help="the error map holds A - B instead of |A - B|")
    parser.add_argument("--scale", type=positive_float, default=1.0, help="multiply the error map by this")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing error map")
    parser.add_argument("--json", action="store_true", help="print the report as JSON (stdout)")
    parser.add_argument("--quiet", "-q", action="store_true", help="print only PASS, WARNING or FAILURE")


def camera_note(a, b) -> str | None:
    """A note when both files record their camera and the two differ (another eye point, pose or lens):
    the images then show different views, and their difference measures that, not a warp's error."""
    import numpy as np

    if a is None or b is None:
        return None
    said = []
    if not np.allclose(a.pose.eye, b.pose.eye, atol=1e-6):
        said.append("eye points " + " and ".join("(" + ", ".join(f"{v:g}" for v in c.pose.eye) + ")" for c in (a, b)))
    if not np.allclose(a.pose.rotation, b.pose.rotation, atol=1e-9):
        said.append("poses")
    if a.lens.spec() != b.lens.spec():
        said.append("lenses")
    return f"the two files record different cameras ({'; '.join(said)}): they show different views" if said else None


def run(args: argparse.Namespace) -> int:
    from lenslab.errors import OutputError
    from lenslab.jobs.funnel import one_line
    from lenslab.jobs.policy import check_output, output_format
    from lenslab.errors import LenslabError
    from lenslab.io import read, write
    from lenslab.metrics.diff import DiffError, diff_images, error_image
    from lenslab.metrics.diff_text import diff_text

    prog = "lenslab diff"

    def file_error(exc) -> int:
        print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
        return EXIT_FILE

    if os.path.isdir(args.second):  # as idiff: a folder holds the file of the first image's name
        args.second = os.path.join(args.second, os.path.basename(args.first))
    fmt = output_format(args.output) if args.output else None  # an unknown extension: a usage error, first
    if args.output:
        try:
            check_output(args.output, [args.first, args.second], args.overwrite)
        except OutputError as exc:
            return file_error(exc)
    images, cameras = [], []
    for path in (args.first, args.second):
        try:
            image, meta = read(path)
        except (LenslabError, OSError, ValueError) as exc:
            return file_error(exc)
        images.append(image)
        cameras.append(meta.get("camera"))
    note = camera_note(*cameras)
    if note and not args.quiet:
        print(f"{prog}: note: {note}", file=sys.stderr)
    t = thresholds_from(args)
    try:
        report = diff_images(images[0], images[1], mask_alpha=not args.no_mask, thresholds=t, flip=args.flip)
    except DiffError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return EXIT_DIFFERENT_SIZE
    if args.output:
        emap = error_image(images[0], images[1], mask_alpha=not args.no_mask, signed=args.signed, scale=args.scale)
        try:
            # errors are small numbers: EXR keeps them in 32-bit float, not half
            write(args.output, emap, overwrite=args.overwrite, **({"pixel_type": "float"} if fmt == "exr" else {}))
        except (LenslabError, OSError) as exc:
            return file_error(exc)
    if args.json:
        import json

        out = report.to_dict()
        out["files"] = [args.first, args.second]
        if args.output:
            out["error_map"] = args.output
        print(json.dumps(out, indent=2))
    elif args.quiet:
        print(report.verdict_name)
    else:
        print(diff_text(report, args.first, args.second))
    return report.verdict
