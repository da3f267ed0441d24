"""Show and convert calibrated cameras: OpenCV, Kalibr, COLMAP, OCamCalib and lenslab camera files.

A camera is a calibration file (OpenCV FileStorage YAML/JSON, Kalibr camchain YAML, COLMAP cameras.txt,
OCamCalib calib_results.txt, lenslab TOML; FILE#ID picks one camera of several) or a lens spec with its
calibration size, e.g. opencv:fx=900,fy=900,cx=639.5,cy=359.5,k1=-0.2,width=1280,height=720.
The same files work wherever lenslab takes a lens (warp --from/--to, fit, tracer).

Examples:
  lenslab camera show calib.yaml
  lenslab camera show sparse/cameras.txt#2
  lenslab camera convert camchain.yaml -o fisheye.yaml           (Kalibr -> OpenCV, read by cv2.FileStorage)
  lenslab camera convert calib.yaml -o cameras.txt               (OpenCV -> COLMAP)
  lenslab camera convert calib_results.txt -o cam.toml --size 1920x1080
  lenslab camera convert ds.yaml -o kb.yaml --model kannala-brandt    (double sphere -> Kannala-Brandt, fitted)

With --model the camera is re-expressed in another model: fitted (nlopt) over the field both cameras
share, starting from the source's image size, principal point and central focal length; the command
prints the RMS and maximum error in pixels and where the maximum lies, and writes OUT only when the
RMS is below --aim (else it says why, with a residual map, and exits with status 1).
"""

from __future__ import annotations

import argparse
import math

from lenslab.calibfiles import FORMATS as CALIBRATION_FORMATS  # light: the plugins load on use

FORMAT_CHOICES = tuple(CALIBRATION_FORMATS)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import image_size

    sub = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    show = sub.add_parser("show", help="print the camera model, its parameters and field of view",
                          description="Print the camera model of a calibration file or spec.")
    show.add_argument("camera", metavar="CAMERA", help="calibration file (FILE or FILE#ID) or lens spec")
    show.add_argument("--size", type=image_size, metavar="WxH", help="show the camera scaled to this image size")
    conv = sub.add_parser("convert", help="write a camera in another calibration format, or another model",
                          description="Convert a camera between OpenCV, Kalibr, COLMAP, OCamCalib and lenslab files; "
                          "with --model, re-express it in another camera model, fitted over the field both share "
                          "(the command prints the RMS and maximum error in pixels and where the maximum lies).")
    conv.add_argument("camera", metavar="CAMERA", help="calibration file (FILE or FILE#ID) or lens spec")
    conv.add_argument("-o", "--output", required=True, metavar="OUT",
                      help="file to write; the format follows its name: .yaml/.json OpenCV (Kalibr for "
                           "double-sphere and eucm), .txt COLMAP (OCamCalib for ocam), .toml lenslab")
    conv.add_argument("--format", choices=FORMAT_CHOICES, help="write this format whatever the name says")
    conv.add_argument("--size", type=image_size, metavar="WxH", help="scale the intrinsics to this image size first")
    conv.add_argument("--overwrite", action="store_true", help="replace OUT if it exists")
    conv.add_argument("--model", metavar="MODEL", help="re-express the camera in this model (a spec: values given "
                      "stay fixed), fitted over the field both share, e.g. kannala-brandt or eucm")
    conv.add_argument("--free", metavar="NAMES", help="with --model: comma-separated parameters to fit (default: "
                      "the model's intrinsics and plain coefficients)")
    conv.add_argument("--aim", type=float, default=0.05, metavar="PX",
                      help="with --model: largest RMS error (px) over the shared field for OUT to be written "
                      "(default 0.05)")
    conv.add_argument("--residual-map", metavar="FILE", help="with --model: write the error (px) at every pixel "
                      "of the source as a float image (EXR, PFM, TIFF); not shared: NaN")


def load(spec: str, size: tuple[int, int] | None):
    from lenslab.errors import LensError
    from lenslab.lenses import make_lens
    from lenslab.lenses.registry import lens_class, parse_spec

    from lenslab.calibfiles import is_camera_file

    if is_camera_file(spec):
        return make_lens(spec, size)  # a calibration file, or an image that records its camera
    name, values = parse_spec(spec)
    if size is None:
        if "width" not in values or "height" not in values:
            if not {p.name for p in lens_class(name, spec).params} >= {"width", "height"}:
                raise LensError(f"{spec}: give the image size with --size WxH")
            raise LensError(f"{spec}: give the calibration size as width=...,height=... (or --size WxH)")
        size = (int(float(values["width"])), int(float(values["height"])))
    return make_lens(spec, size)


def field_of_view(lens) -> tuple[float, float]:
    """Angles (degrees) between the left and right edges and the top and bottom edges, through the
    image centre (NaN where an edge is not seen)."""
    import numpy as np

    w, h = lens.width, lens.height
    d, ok = lens.pixel_to_dir(np.array([[0.0, h / 2], [w, h / 2], [w / 2, 0.0], [w / 2, h]]))

    def angle(a, b):
        if not (ok[a] and ok[b]):
            return math.nan
        za = np.arccos(np.clip(d[a, 2], -1, 1))
        zb = np.arccos(np.clip(d[b, 2], -1, 1))
        return math.degrees(za + zb)

    return angle(0, 1), angle(2, 3)


def run(args: argparse.Namespace) -> int:
    from lenslab.errors import LensError

    import warnings

    if args.action == "convert":  # usage errors, found before the camera is read
        from lenslab.calibfiles import split_pick
        from lenslab.jobs.policy import refuse_inputs

        if not args.model and (args.free or args.residual_map or args.aim != 0.05):
            from lenslab.errors import UsageError

            raise UsageError("--free, --aim and --residual-map go with --model MODEL")
        # the file read named as an output (OUT or the residual map)
        refuse_inputs([args.output] + ([args.residual_map] if args.residual_map else []),
                      [split_pick(args.camera)[0]])
    mirror = recorded_mirror(args.camera)
    if mirror and args.action == "convert":
        raise LensError(f"{args.camera}: records a mirrored camera (mirror {mirror}, as warp --flip writes it), and a "
                        f"camera file gives a lens without its mirror, which would see the image mirrored; name the "
                        f"image itself where a camera goes (--from/--to {args.camera})")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lens = load(args.camera, args.size)
    import sys

    for note in dict.fromkeys(str(w.message) for w in caught):  # which reading was taken, and how to choose
        print(f"{args._prog}: note: {note}", file=sys.stderr)
    if args.action == "show":
        from lenslab.lenses.core.base import format_number

        print(f"{args.camera}: {lens.name} ({lens.summary}), {lens.width}x{lens.height}")
        for k, v in lens.param_values().items():
            print(f"  {k:8s} {format_number(v) if isinstance(v, float) else v}")
        hfov, vfov = field_of_view(lens)
        text = lambda a: "beyond the image" if math.isnan(a) else f"{a:.2f} deg"  # noqa: E731
        print(f"  field across the width {text(hfov)}, across the height {text(vfov)} (through the centre)")
        print(f"  spec: {lens.spec()}")
        if mirror:
            print(f"  mirror   {mirror} (its pixels show the world mirrored, as warp --flip wrote them)")
        return 0
    from lenslab.calibfiles import split_pick, write_lens
    from lenslab.jobs.policy import check_output

    src, _ = split_pick(args.camera)
    out = check_output(args.output, [src] if src.exists() else [], args.overwrite)
    if args.model:
        lens = _convert_model(args, lens, [src] if src.exists() else [])
    try:
        write_lens(out, lens, args.format, overwrite=args.overwrite)
    except LensError as exc:
        msg = str(exc)
        raise LensError(msg if msg.startswith(str(out)) else f"{out}: {msg}") from None
    print(f"{out}: {lens.name} {lens.width}x{lens.height}")
    return 0


def recorded_mirror(spec: str) -> str:
    """The mirror (``h``, ``v``, ``d``) of the camera an image named as CAMERA records (``lenslab warp --flip`` wrote
    it), else "": no calibration file holds one, so such an image converts to none (its lens alone would read its
    pixels back mirrored)."""
    from lenslab.jobs.warp.cameras import recorded_view

    view = recorded_view(spec)
    return view.pose.mirror if view is not None else ""


def _convert_model(args, lens, inputs):
    from lenslab import io
    from lenslab.jobs.policy import check_output
    from lenslab.errors import FitError
    from lenslab.fit.convert import convert_lens

    if not args.aim > 0:
        from lenslab.errors import UsageError

        raise UsageError(f"--aim {args.aim:g}: give a positive number of pixels")
    resmap = check_output(args.residual_map, inputs + [args.output], args.overwrite) if args.residual_map else None
    import sys

    from lenslab.jobs.progress import RowBar

    # a fit takes seconds: on a terminal, one line says so once it has taken longer than a second
    said = RowBar(args.camera, sys.stderr) if sys.stderr.isatty() else None
    if said is not None:
        said.status(f"fitting the {args.model} model over the field both cameras share")
    try:
        conv = convert_lens(lens, args.model, free=args.free, aim=args.aim)
    finally:
        if said is not None:
            said.close()
    print("\n".join(conv.report()))
    if resmap is not None:
        io.write(resmap, conv.image((lens.width, lens.height)), overwrite=args.overwrite)
        print(f"{resmap}: residual map (px)")
    if not conv.met:
        raise FitError(f"{args.output}: not written: the {args.model} fit misses the aim (RMS {conv.rms:.3g} px, "
                       f"aim {args.aim:g} px)")
    return conv.lens
