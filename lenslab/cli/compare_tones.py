"""Side-by-side strip of one HDR image under several tone curves, each panel labelled with its curve.

Every panel gets the same exposure (stops, or 'auto' chosen once from the image) and mode.
Panels wider than --panel-width are shrunk with area averaging (in linear light). --display adds a
last panel: the OpenColorIO display transform of the same exposed image, its code values shown as
they are, beside the curves (SDR displays; PQ and HLG need an HDR file: lenslab tonemap --display).

  lenslab compare-tones pano.exr -o strip.jpg --curves clamp,reinhard,hable
  lenslab compare-tones pano.exr -o strip.png --curves hable,aces,agx,pbr-neutral --exposure auto --vertical
  lenslab compare-tones pano.exr -o strip.png --curves hable,agx --display sRGB --view 'ACES 2.0 - SDR'
"""

from __future__ import annotations

import argparse
import sys

from lenslab.jobs.arguments import non_negative_int


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", help="HDR image to read")
    parser.add_argument("-o", "--output", required=True, help="strip image to write (JPG, PNG, ...)")
    from lenslab.jobs.arguments import add_tone_mode_option, add_tones_option

    add_tones_option(parser, default="clamp,reinhard,hable",
                     help="comma-separated curve names, left to right (default clamp,reinhard,hable: no curve, the "
                          "classic photographic curve and a filmic one)")
    parser.add_argument("--exposure", default="0", help="exposure in stops for every panel, or 'auto' (default 0)")
    add_tone_mode_option(parser, "curves act on each channel (default)", "curves act on luminance (keeps hue)")
    parser.add_argument("--panel-width", type=non_negative_int, default=1024,
                        help="shrink panels wider than this many pixels (0: keep full size; default 1024)")
    parser.add_argument("--vertical", action="store_true", help="stack panels top to bottom instead")
    parser.add_argument("--primaries", default=None,
                        help="primaries the image's values are on, for the luminance weights of --luminance, "
                             "--exposure auto and the curves that read luminance (default sRGB); for files without "
                             "a colour tag: a file with an ICC profile, cICP chunk or EXR chromaticities is read "
                             "onto sRGB's primaries, and sRGB's weights apply to it")
    parser.add_argument("--dither", action=argparse.BooleanOptionalAction, default=True,
                        help="dither when quantising (default on)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing output file (never the input)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors and repairs")
    from lenslab.cli.display import add_display_arguments

    add_display_arguments(parser, "a panel more: an OpenColorIO display transform of the same exposed image",
                          hdr=False)


def label_panel(panel, text: str):
    """Write ``text`` in the top-left corner of a float image (white on a dark outline), in place.

    OpenCV draws text on 8-bit images only: the glyphs are drawn into 8-bit masks (anti-aliased) and
    blended into the float panel.
    """
    import cv2
    import numpy as np

    h, w = panel.shape[:2]
    scale = max(0.5, min(w, h) / 400.0)
    thick = max(1, round(scale * 2))
    org = (int(10 * scale), int(30 * scale))
    outline = np.zeros((h, w), np.uint8)
    fill = np.zeros((h, w), np.uint8)
    cv2.putText(outline, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, 255, thick * 3, cv2.LINE_AA)
    cv2.putText(fill, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, 255, thick, cv2.LINE_AA)
    dark = (outline.astype(np.float32) / 255)[..., None]
    light = (fill.astype(np.float32) / 255)[..., None]
    panel *= 1 - dark
    panel += light
    np.clip(panel, 0, 1, out=panel)
    return panel


def run(args: argparse.Namespace) -> int:
    import cv2
    import numpy as np

    from lenslab import io, tone
    from lenslab.cli.tonemap import repairs_reported
    from lenslab.errors import ToneError
    from lenslab.io.registry import format_for_path, get
    from lenslab.jobs.policy import check_output
    from lenslab.jobs.stages import Look, develop
    from lenslab.jobs.tonemap import write_tone_mapped

    names = [tone.get_curve(n).name for n in args.curves.split(",") if n.strip()]
    if not names:
        raise ToneError(f"--curves is empty; give names from: {', '.join(tone.CURVES)}")
    display = display_panel_options(args)
    from lenslab.jobs.primaries import applied_primaries, check_primaries

    check_primaries(args.primaries, args.mode, args.exposure, [tone.get_curve(n) for n in names])
    check_output(args.output, [args.input], args.overwrite)
    from lenslab.jobs.policy import output_format

    output_format(args.output)  # an unknown extension: one usage error before the image is read
    fmt = get(format_for_path(args.output, None))
    image, meta = io.read(args.input)
    with repairs_reported("lenslab compare-tones", args.input):  # a file read onto Rec.709: sRGB's weights, said
        args.primaries = applied_primaries(args.primaries, meta)
    if image.ndim == 2:
        image = image[..., None]
    from lenslab.io import carries_alpha
    from lenslab.jobs.stages import resolved_exposure

    alpha = carries_alpha(meta, image.shape[2])
    from lenslab.io.colour.gamut import clip_outside

    # a wide-gamut file's colours outside sRGB, said once: clipped for the curves, not for the display transform,
    # which is given the file's own colours as tonemap --display gives them
    source = image if display["display"] else None
    image = clip_outside(image, meta, alpha, in_place=source is None)
    # auto exposure from the covered pixels' straight colour (lenslab.tone.exposure), then the colour over black
    ev = resolved_exposure(image, args.exposure, args.primaries, args.input, args.quiet, alpha)
    if alpha:
        image = image[..., :-1]
        source = None if source is None else source[..., :-1]
    from contextlib import nullcontext

    from lenslab.current_input import from_input
    from lenslab.tone.repairs import uncounted

    panels = []
    for i, name in enumerate(names):  # the look stage of every job: exposure, then the curve
        # the input's repairs said once, its slight ones counted once: the panels are one file's
        with repairs_reported("lenslab compare-tones", args.input, report=i == 0), from_input(args.input), \
                (nullcontext() if i == 0 else uncounted()):
            out, _ = develop(image, {}, fmt, Look(tone=name, exposure=ev, mode=args.mode, primaries=args.primaries,
                                                  always=True))
        h, w = out.shape[:2]
        if args.panel_width and w > args.panel_width:
            size = (args.panel_width, max(1, round(h * args.panel_width / w)))
            out = cv2.resize(out, size, interpolation=cv2.INTER_AREA)
            if out.ndim == 2:
                out = out[..., None]
        panels.append(np.ascontiguousarray(out))
    labels = list(names)
    if display["display"]:  # the strip in code values: the curves' panels sRGB-encoded, the display's as it is
        from lenslab.io.ocio import processor
        from lenslab.srgb import encode

        panels = [encode(p) for p in panels]
        shown, _ = develop(source, {}, fmt, Look(exposure=ev, **display))  # the look stage's display transform
        h, w = shown.shape[:2]
        if args.panel_width and w > args.panel_width:
            shown = cv2.resize(shown, (args.panel_width, max(1, round(h * args.panel_width / w))),
                               interpolation=cv2.INTER_AREA)
        panels.append(np.ascontiguousarray(np.clip(shown.reshape(panels[0].shape), 0, 1), np.float32))
        _, (d, v, _) = processor(display["display"], display["view"], display["colorspace"], display["ocio"])
        labels.append(v)
    panels = [label_panel(p, text) for p, text in zip(panels, labels)]
    gap_shape = list(panels[0].shape)
    if args.vertical:
        gap_shape[0] = 4
    else:
        gap_shape[1] = 4
    gap = np.ones(gap_shape, np.float32)
    parts = []
    for i, p in enumerate(panels):
        parts.extend([gap, p] if i else [p])
    strip = np.concatenate(parts, axis=0 if args.vertical else 1)
    if display["display"]:
        io.write(args.output, strip, overwrite=args.overwrite, raw=True, dither=args.dither)
    else:
        write_tone_mapped(args.output, strip, dither=args.dither, overwrite=args.overwrite)
    if not args.quiet:
        print(f"{args.output}: {strip.shape[1]} x {strip.shape[0]}, panels {', '.join(labels)}", file=sys.stderr)
    return 0


def display_panel_options(args: argparse.Namespace) -> dict:
    """The ``--display`` options, checked: an SDR display, an output that holds code values, exposure in stops."""
    from lenslab.cli.display import display_options
    from lenslab.errors import UsageError
    from lenslab.io.detect import format_for_path
    from lenslab.io.ocio import is_hdr_display
    from lenslab.io.registry import get

    display = display_options(args)
    if display["display"] is None:
        return display
    if is_hdr_display(display["display"]):
        raise UsageError(f"--display {display['display']}: the strip is an SDR image; write an HDR display with "
                         "lenslab tonemap --display")
    if "raw" not in get(format_for_path(args.output, None)).write_options:
        raise UsageError(f"{args.output}: a strip with a display panel holds display code values: write png, jpg, "
                         "ppm or tif")
    return display
