"""Fit lens models and tone curves with nlopt.

  lenslab fit lens --from SPEC --model MODEL [--size WxH]
      the parameters of MODEL whose pixel -> direction mapping best matches SPEC over the image,
      e.g. --from distortion:k1=-0.05,fov=60 --model brown, or --from fisheye:fov=190,mapping=equisolid
      --model fisheye (the mapping is found too). Prints the fitted spec and the residual in pixels
      (RMS, maximum and where it is).

  lenslab fit points FILE.csv --model MODEL --size WxH [--source SPEC] [--pose]
      calibration from measured points: CSV rows x,y,dx,dy,dz or x,y,lon,lat (pixel and the direction
      it sees), or src_x,src_y,x,y (the same feature in a known --source camera and in the unknown one).
      A robust loss keeps a few wrong points from spoiling the fit; every point's residual is listed.

  lenslab fit tone HDR LDR --tone hable
      the exposure and curve parameters that make the tone-mapped HDR image reproduce the LDR one,
      with the CIEDE2000 colour difference before and after.

In a model spec, parameters you give stay fixed and the others are fitted (numbers) or tried in turn
(choices such as a fisheye's mapping); --free names the fitted ones instead. `fit lens` and `fit points`
exit 0 for a good fit and 1 when the fit falls short (the report says why). `fit tone` exits 1 only when
its search does not converge: a converged fit of two images that do not match still exits 0, with a
note when the mean CIEDE2000 left is above 10; judge it by the colour difference it reports.
"""

from __future__ import annotations

import argparse
import sys


def _size(text: str) -> tuple[int, int]:
    try:
        w, _, h = text.lower().partition("x")
        size = int(w), int(h)
        if min(size) < 1:
            raise ValueError
        return size
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT, for example 1024x768, got {text!r}") from None


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--free", metavar="NAMES", help="comma-separated parameters to fit (default: every numeric "
                   "parameter the model spec does not give, but tangential, thin prism and rational terms)")
    p.add_argument("--bounds", metavar="NAME=LO:HI,...", help="ranges of fitted parameters, e.g. k1=-0.5:0.5 "
                   "(default: the model's own range; start +- max(1, |start|) where it has none)")
    p.add_argument("--global", dest="global_start", default="auto", choices=("auto", "none", "direct-l", "mlsl"),
                   help="global search before the local one: auto (only when the local fit falls short), "
                   "none, direct-l or mlsl (default: auto)")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_float, positive_int

    sub = parser.add_subparsers(dest="fit_kind", metavar="KIND")
    sub.required = True

    p = sub.add_parser("lens", help="fit one lens model to another over the image",
                       description="Fit MODEL's parameters to reproduce the lens SPEC over the whole image.")
    p.add_argument("--from", dest="source", required=True, metavar="SPEC", help="the lens to reproduce")
    p.add_argument("--model", required=True, metavar="MODEL", help="the model to fit (a spec; given values stay fixed)")
    p.add_argument("--size", type=_size, metavar="WxH", help="image size (default: a calibrated camera's own, "
                   "else 1024x1024; 1024x512 for equirect)")
    p.add_argument("--space", choices=("direction", "pixel"), default="direction",
                   help="residual minimised: direction (angle between the rays, in pixels through the fitted "
                   "lens's local scale; forward maps only) or pixel (where the fitted lens puts the source's "
                   "ray; uses its inverse). Default: direction")
    p.add_argument("--tolerance", type=positive_float, default=0.5, metavar="PX",
                   help="largest residual (pixels) accepted as a good fit (default 0.5)")
    _common(p)

    p = sub.add_parser("points", help="calibrate a lens from measured points (robustly)",
                       description="Fit MODEL (and optionally its orientation) to measured pixel <-> direction pairs.")
    p.add_argument("csv", metavar="FILE.csv", help="the points: x,y,dx,dy,dz | x,y,lon,lat | src_x,src_y,x,y")
    p.add_argument("--model", required=True, metavar="MODEL", help="the model to fit (a spec; given values stay fixed)")
    p.add_argument("--size", type=_size, required=True, metavar="WxH", help="size of the unknown camera's image")
    p.add_argument("--source", metavar="SPEC", help="the known camera of src_x,src_y pixel pairs")
    p.add_argument("--source-size", type=_size, metavar="WxH",
                   help="its image size (default: the image's own for --source IMAGE that records its camera, "
                        "else --size)")
    p.add_argument("--pose", action="store_true", help="also fit yaw, pitch and roll (directions are world directions)")
    p.add_argument("--loss", default="cauchy", choices=("cauchy", "huber", "soft_l1", "arctan", "linear"),
                   help="robust loss for the first pass (default cauchy: far outliers pull with almost no force)")
    p.add_argument("--scale", type=positive_float, default=1.0, metavar="PX",
                   help="residual (pixels) where the loss turns robust; about the measuring precision (default 1)")
    p.add_argument("--outlier", type=positive_float, metavar="PX", help="residual above which a point is an outlier and left "
                   "out of the final least-squares pass (default 3 x --scale)")
    p.add_argument("--brief", action="store_true", help="do not list every point's residual")
    _common(p)

    p = sub.add_parser("tone", help="fit exposure and tone-curve parameters to reproduce an LDR image",
                       description="Fit exposure and curve parameters so that the tone-mapped HDR reproduces the LDR.")
    p.add_argument("hdr", metavar="HDR", help="scene-linear image (EXR, PFM, ...)")
    p.add_argument("ldr", metavar="LDR", help="display image of the same view and size (JPG, PNG, PPM, ...)")
    from lenslab.jobs.arguments import add_tone_option

    add_tone_option(p, "curve", default="hable", help="tone curve to fit (default hable; see 'lenslab curves')")
    p.add_argument("--mode", default="per-channel", choices=("per-channel", "luminance"),
                   help="apply the curve per channel or on luminance (default per-channel)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="hold a curve parameter (or exposure) at a value; repeatable")
    p.add_argument("--max-pixels", type=positive_int, default=1 << 16, metavar="N",
                   help="pixels the fit looks at, evenly spread (default 65536)")
    p.add_argument("--free", metavar="NAMES", help="comma-separated names to fit, exposure included (default: "
                   "exposure and the curve's own numeric parameters, except those that duplicate exposure)")
    p.add_argument("--bounds", metavar="NAME=LO:HI,...", help="ranges of fitted parameters")
    p.add_argument("--global", dest="global_start", default="auto", choices=("auto", "none", "direct-l", "mlsl"),
                   help="global search: auto (when the local fit is more than one 8-bit code off), none, "
                   "direct-l or mlsl (default auto)")


def _global(value: str):
    return None if value == "none" else value


def run(args) -> int:
    from lenslab.errors import FitError

    kind = args.fit_kind
    if kind == "lens":
        return _run_lens(args, FitError)
    if kind == "points":
        return _run_points(args, FitError)
    return _run_tone(args, FitError)


def _run_lens(args, FitError) -> int:
    from lenslab.fit.lens import fit_lens
    from lenslab.lenses import make_lens, parse_spec
    from lenslab.lenses.registry import lens_class

    from lenslab.calibfiles import is_camera_file

    size = args.size
    if size is None and is_camera_file(args.source):  # a calibration file: its own image size
        source = make_lens(args.source)
    elif size is None:
        name, values = parse_spec(args.source)
        size = getattr(lens_class(name), "default_size", None) or ((1024, 512) if name == "equirect" else (1024, 1024))
        if values.get("width") and values.get("height"):  # a calibrated spec: its calibration image
            size = (int(float(values["width"])), int(float(values["height"])))
    if size is not None:
        source = make_lens(args.source, size)
    result = fit_lens(source, args.model, free=args.free, bounds=args.bounds, space=args.space,
                      global_start=_global(args.global_start), tolerance=args.tolerance)
    print("\n".join(result.report()))
    if not result.ok:
        raise FitError(f"no good fit: {result.reason()}")
    return 0


def _run_points(args, FitError) -> int:
    from lenslab.fit.points import fit_points, read_points

    source = None
    if args.source:
        from lenslab.jobs.warp.cameras import lens_camera

        # (an image's camera at its own size unless --source-size; a flop's with its mirror)
        source = lens_camera(args.source, args.source_size or args.size, own_size=args.source_size is None)
    pts = read_points(args.csv, source)
    result = fit_points(pts, args.model, args.size, free=args.free, bounds=args.bounds, pose=args.pose,
                        loss=args.loss, scale=args.scale, outlier=args.outlier,
                        global_start=_global(args.global_start))
    print("\n".join(result.report(per_point=not args.brief)))
    if not result.ok:
        raise FitError("no good fit: too few points agree with the fitted camera; check the points and the model")
    return 0


def _run_tone(args, FitError) -> int:
    from lenslab import io
    from lenslab.errors import FitSpecError
    from lenslab.fit.params import parse_bounds
    from lenslab.fit.tone import fit_tone, tone_variables

    fixed = {}
    for item in args.param:
        name, eq, value = item.partition("=")
        if not eq or not name.strip():
            raise FitSpecError(f"--param {item!r}: expected NAME=VALUE, for example white=8")
        try:
            fixed[name.strip()] = float(value)
        except ValueError:
            fixed[name.strip()] = value.strip()
    tone_variables(args.curve, args.free, parse_bounds(args.bounds), fixed)  # names checked before any read
    hdr, _ = io.read(args.hdr)
    ldr, _ = io.read(args.ldr)
    result = fit_tone(hdr, ldr, args.curve, mode=args.mode, free=args.free, fixed=fixed, bounds=args.bounds,
                      global_start=_global(args.global_start), max_pixels=args.max_pixels)
    print("\n".join(result.report()))
    if not result.optimizer.converged:
        raise FitError("the tone fit did not converge; the values above are the best found")
    return 0


if __name__ == "__main__":  # pragma: no cover
    from lenslab.cli.main import main

    sys.exit(main(["fit"] + sys.argv[1:]))
