"""Print what image files hold: format, size, channels, sample type, per-channel min/mean/max (over
finite values), counts of NaN, infinite and negative values, and the lens model if the file carries
a camera (EXR files written by lenslab do). A photo that names its camera, lens or focal length in its
metadata gets the lensfun profile 'lensfun:auto' would use, and the pinhole '--from exif' would give (the
field of view of its 35 mm equivalent focal length, for the photo as shown). Then the file's structure: every EXR part with its
storage, compression, data and display windows, layers, channels (pixel type and sampling) and
attributes; TIFF pages; the Radiance header; the streams of a video; which rendition of an Ultra HDR
JPEG is read (HDR, or the SDR base with 'file.jpg:sdr') and its gain map's metadata (headroom in stops).

EXR selectors work here too: 'file.exr:left' (a layer), 'file.exr:2' or 'file.exr:NAME' (a part); 'photo.jpg:sdr'
reads an Ultra HDR JPEG's SDR base image.
'lenslab info --formats' lists every format lenslab reads and writes, with what each holds and the --pixel-type
samples each is written with.

examples:
  lenslab info pano.exr
  lenslab info IMG_0042.jpg          (a photo: its lens, and the --from it gives a warp)
  lenslab info --json renders/*.exr > stats.json
  lenslab info --formats
"""

from __future__ import annotations

import argparse
import json
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="*", metavar="FILE",
                        help="image or video files (see --formats for the formats lenslab knows)")
    parser.add_argument("--formats", action="store_true",
                        help="list the formats lenslab reads and writes, with what each holds "
                             "and the --pixel-type samples each is written with")
    parser.add_argument("--json", action="store_true", help="print one JSON list with an object per file")
    parser.add_argument("--raw", action="store_true",
                        help="statistics of the stored code values (scaled to 0..1) instead of linear light")
    parser.add_argument("--data-window", action="store_true",
                        help="EXR: statistics of the stored data window, not the display window")


def describe(path: str, raw: bool = False, data_window: bool = False) -> dict:
    """Everything ``info`` prints about one file, as a JSON-ready dict."""
    import numpy as np

    from lenslab.io import read, split_selector
    from lenslab.io.probe import probe
    from lenslab.io.registry import get, sniff

    file, _ = split_selector(path)
    fmt = get(sniff(file))
    if fmt.kind == "video":  # many frames: the streams are what it holds
        return {"file": str(path), "format": fmt.name, "video": fmt.probe(file)}
    import warnings

    from lenslab.io.exr import MultiPartWarning
    from lenslab.io.ldr import GainMapWarning

    with warnings.catch_warnings():  # notes of what info lists itself: the parts of a file, a gain map
        warnings.simplefilter("ignore", MultiPartWarning)
        warnings.simplefilter("ignore", GainMapWarning)
        image, meta = read(path, raw=raw, data_window=data_window)
    stats = []
    for i, name in enumerate(meta["channels"]):
        ch = image[..., i]
        finite = np.isfinite(ch)
        vals = ch[finite] if not finite.all() else ch
        stats.append({
            "channel": name,
            "min": float(vals.min()) if vals.size else None,
            "mean": float(vals.mean(dtype=np.float64)) if vals.size else None,
            "max": float(vals.max()) if vals.size else None,
            "nan": int(np.isnan(ch).sum()),
            "inf": int(np.isinf(ch).sum()),
            "negative": int((ch < 0).sum()),
        })
    camera = meta.get("camera")
    out = {
        "file": str(path),
        "format": meta["format"],
        "width": meta["size"][0],
        "height": meta["size"][1],
        "channels": meta["channels"],
        "bit_depth": meta["bit_depth"],
        "sample_type": meta["sample_type"],
        "display_encoded": meta["display_encoded"],
        "stats": stats,
        "lens": camera.lens.spec() if camera is not None else None,
        "camera": camera.to_dict() if camera is not None else None,
        "lens_tiles": _recorded_tiles(camera.lens) if camera is not None else None,
    }
    for key in ("part", "part_name", "layer", "data_window", "display_window", "ignored_channels", "extra_channels",
                "luminance_chroma", "primaries_converted_to_rec709", "view", "other_views", "deep"):
        if key in meta:
            out[key] = meta[key]
    if camera is None:  # the lens the photo's metadata names, and the lensfun profile lensfun:auto uses
        from lenslab.io.exif_orientation import stored_size
        from lenslab.lenses.lensfun.match import metadata_report

        size = tuple(meta["size"])
        out["lens_metadata"] = metadata_report(file, size, stored_size(file, size))
    attrs = {k: v for k, v in meta["attributes"].items() if k != "lenslab.camera"}
    tiles = (meta.get("exr_header") or {}).get("tiles")
    if "tiles" in attrs and tiles is not None and "data_window" in meta:  # the words convert's note uses
        from lenslab.io.exr.keep import tiling

        attrs["tiles"] = tiling(tiles, meta["data_window"])[0]
    out["attributes"] = attrs
    out["structure"] = probe(file, fmt.name)
    if "lenslab:stmap" not in attrs:  # a map another tool made: said, and read as the picture it is stored as
        from lenslab.stmap_lookalike import st_map_way

        way = st_map_way(image, meta["channels"])
        out["looks_like_st_map"] = way is not None
        if way == 1:  # its second coordinate grows downward: --stmap would read it upside down
            out["st_map_upside_down"] = True
    return out


def _gain_applied(d: dict) -> bool:
    """Whether an 8-bit file was read as its HDR rendition (an Ultra HDR JPEG's gain map applied)."""
    from lenslab.io.gainmap import HDR_RENDITION

    return str((d.get("attributes") or {}).get("rendition", "")).startswith(HDR_RENDITION)


def _recorded_tiles(lens) -> list[str] | None:
    """Each tile of a grid whose spec does not name its tiles (tiles recorded in the file, not the default tiles
    nor a tiles file): its lens and pose; None for any other lens."""
    tiles = getattr(lens, "tile_list", None)
    if tiles is None or getattr(lens, "tiles_path", ""):
        return None
    from lenslab.lenses.registry import make_lens

    if make_lens(lens.spec(), (lens.width, lens.height)) == lens:
        return None
    return [f"{k}: " + ("no camera" if t is None else f"{t.lens.spec()}; {_pose_words(t.pose.to_dict())}")
            for k, t in enumerate(tiles)]


def _pose_words(camera: dict) -> str:
    """``yaw 30, pitch -10, roll 0 degrees; eye (0, 1.5, 0)`` of a camera's :meth:`~lenslab.Camera.to_dict`."""
    def num(v: float) -> str:
        return f"{round(float(v), 9) + 0.0:.6g}"  # (+ 0.0: no "-0"; 1e-16 of a matrix's rounding: 0)

    turn = (f"yaw {num(camera['yaw'])}, pitch {num(camera['pitch'])}, roll {num(camera['roll'])} degrees"
            if "yaw" in camera else "rotation " + str([[float(num(v)) for v in row] for row in camera["rotation"]]))
    if camera.get("mirror"):  # a mirrored view (warp --flip): the lens's rays reflected, then turned
        sides = {"h": "left-right", "v": "up-down", "d": "front-back"}
        turn = f"mirrored {' and '.join(sides[c] for c in camera['mirror'])} ({camera['mirror']}), then {turn}"
    return f"{turn}; eye ({', '.join(num(v) for v in camera['eye'])})"


def _structure_lines(d: dict) -> list[str]:
    st = d.get("structure") or {}
    lines = []
    for p in st.get("parts", []):
        lines.append(f"  part {p['index']} ({p['name'] or 'unnamed'}): "
                     f"{p['storage']}, {p['compression']} compression, data window {p['data_window']}, display "
                     f"window {p['display_window']}, {p['line_order']}")
        chans = ", ".join(c["name"] + " " + c["type"] + ("" if c["sampling"] == [1, 1] else
                                                          f" {c['sampling'][0]}x{c['sampling'][1]}-sampled")
                          for c in p["channels"])
        lines.append(f"    channels: {chans}")
        if p.get("deep_samples"):
            n = p["deep_samples"]
            lines.append(f"    deep: {n['total']} samples in {n['pixels']} pixels, at most {n['max_per_pixel']} in one "
                         "pixel")
        if p["layers"]:
            lines.append(f"    layers: {', '.join(p['layers'])}")
        for k, v in p["attributes"].items():
            if k != "lenslab.camera":
                lines.append(f"    {k}: {v}")
    for i, p in enumerate(st.get("pages", [])):
        lines.append(f"  page {i}: {p['axes']} {p['shape']} {p['dtype']}, {p['compression']} compression, "
                     f"{p['photometric']}, {p['planar']}" + (f", extra samples {p['extrasamples']}"
                                                              if p["extrasamples"] else ""))
    more = st.get("page_count", 0) - len(st.get("pages", []))
    if more > 0:
        lines.append(f"  ... and {more} more page(s) (lenslab reads page 0)")
    if "resolution" in st:
        lines.append(f"  resolution line: {st['resolution']}")
    return lines


def _frames(stream: dict, duration: float | None) -> str:
    """A video stream's frame count as its header gives it, or (a container that counts none, Matroska's) the count
    its duration and rate make, said as such."""
    from fractions import Fraction

    if stream["frames"]:
        return f"{stream['frames']} frames"
    try:
        return f"about {round(duration * Fraction(stream['frame_rate']))} frames (from its duration; the container " \
               "does not count them)"
    except (TypeError, ValueError, ZeroDivisionError):  # no duration or no rate: nothing to count from
        return "frames not counted by the container"


def _video_text(d: dict) -> str:
    v = d["video"]
    dur = f", {v['duration_s']:.3f} s" if v["duration_s"] is not None else ""
    lines = [f"{d['file']}: video ({v['container']}{dur}), {len(v['streams'])} stream(s)"]
    for s in v["streams"]:
        if s["kind"] == "video":
            lines.append(f"  stream {s['index']}: video {s['codec']} {s['width']} x {s['height']} {s['pixel_format']}, "
                         f"{s['frame_rate']} fps, {_frames(s, v['duration_s'])}, primaries {s['colour_primaries']}, "
                         f"transfer {s['transfer']}, matrix {s['matrix']}, range {s['range']}")
        elif s["kind"] == "audio":
            lines.append(f"  stream {s['index']}: audio {s['codec']} {s['sample_rate']} Hz, {s['channels']} channel(s)")
        else:
            lines.append(f"  stream {s['index']}: {s['kind']} {s['codec']}")
    return "\n".join(lines)


def formats_text() -> str:
    """The table printed by ``lenslab info --formats``, from the format plugins: what each format holds, and the
    ``--pixel-type``s a file of it is written with (:attr:`~lenslab.io.plugin.Format.pixel_types`)."""
    from lenslab.io.registry import formats

    rows = [(f, ("linear HDR" if f.hdr else "display-encoded") + (", alpha" if f.alpha else "")
             + f", {'/'.join(str(b) for b in f.bit_depths)}-bit", written_types(f), " ".join(f.extensions))
            for f in formats().values()]
    widths = [max([len(head)] + [len(r[i]) for r in rows]) for i, head in ((1, "holds"), (2, "--pixel-type"),
                                                                           (3, "extensions"))]
    wh, wt, we = widths  # columns as wide as their longest entry
    lines = [f"{'format':<7s} {'read':<5s} {'write':<6s} {'holds':<{wh}s} {'--pixel-type':<{wt}s} "
             f"{'extensions':<{we}s} notes"]
    for f, holds, types, ext in rows:
        lines.append(f"{f.name:<7s} {'yes' if f.readable else '-':<5s} {written(f):<6s} "
                     f"{holds:<{wh}s} {types:<{wt}s} {ext:<{we}s} {f.note}".rstrip())
    return "\n".join(lines)


def written(fmt) -> str:
    """``yes`` where lenslab writes files of format record ``fmt``: an image format's writer, or a clip
    (``lenslab warp`` and ``lenslab convert`` encode it; no image writer does), else ``-``."""
    return "yes" if fmt.writable or fmt.kind == "video" else "-"


def written_types(fmt) -> str:
    """The ``--pixel-type``s format record ``fmt`` is written with, as ``uint8/uint16``; ``-`` where none applies (a
    format lenslab only reads, a clip, whose samples are its codec's)."""
    return "/".join(fmt.pixel_types) if fmt.writable and fmt.kind == "image" else "-"


def _text(d: dict) -> str:
    from pathlib import Path

    from lenslab.io import split_selector

    lines = [f"{d['file']}: {d['format'].upper()} {d['width']} x {d['height']}, {len(d['channels'])} channel(s) "
             f"{','.join(d['channels'])}, {d['sample_type']} {d['bit_depth']}-bit"
             f"{', sRGB-decoded to linear' if d['display_encoded'] else ''}"
             f"{', read as its HDR rendition: linear light' if _gain_applied(d) else ''}"]
    if d.get("layer"):
        lines.append(f"  layer {d['layer']} of part {d['part']}")
    parts = (d.get("structure") or {}).get("parts", [])
    if len(parts) > 1:  # which of the parts listed below the statistics are of
        name = Path(split_selector(d["file"])[0]).name
        lines.append(f"  statistics of part {d['part']} ({d.get('part_name') or 'unnamed'}) of the {len(parts)} "
                     f"listed below; pick another as {name}:NAME or {name}:INDEX")
    if d.get("deep"):  # a deep part: what the image was made from
        deep = d["deep"]
        lines.append(f"  flattened from {deep['samples']} deep samples (at most {deep['max_per_pixel']} in one pixel): "
                     "sorted by depth, composited front to back with over")
    if d.get("luminance_chroma"):
        lines.append("  luminance/chroma (Y, RY, BY) converted to RGB")
    if d.get("primaries_converted_to_rec709"):
        lines.append("  colour converted from the file's chromaticities to Rec.709 primaries")
    if d.get("other_views"):  # one view of a multi-view part: the others are neither read nor written
        rest = d["other_views"]
        shown = ", ".join(rest[:12]) + (f" and {len(rest) - 12} more" if len(rest) > 12 else "")
        lines.append(f"  view {d['view']} alone: {len(rest)} channel(s) of the other views not read: {shown}")
    others = d.get("extra_channels") or d.get("ignored_channels")
    if others:  # every channel of the part beside the image's: what convert to EXR keeps, other formats drop
        shown = ", ".join(others[:12]) + (f" and {len(others) - 12} more" if len(others) > 12 else "")
        lost = [n for n in others if n in d["channels"]]  # a layer read alone takes the base channels' names
        kept = f"EXR output keeps them but {', '.join(lost)}" if lost else "EXR output keeps them"
        lines.append(f"  {len(others)} other channel(s), not in the image ({kept}): {shown}")
    lines.append(f"  {'channel':<8s} {'min':>12s} {'mean':>12s} {'max':>12s} {'NaN':>8s} {'inf':>8s} {'negative':>9s}")

    def num(v):
        return f"{v:12.6g}" if v is not None else f"{'-':>12s}"

    for s in d["stats"]:
        lines.append(f"  {s['channel']:<8s} {num(s['min'])} {num(s['mean'])} {num(s['max'])} "
                     f"{s['nan']:8d} {s['inf']:8d} {s['negative']:9d}")
    lines.append(f"  lens: {d['lens']}" if d["lens"] else "  lens: none stored")
    if d.get("camera"):  # where the stored camera looks (a warp from this file starts from it)
        lines.append(f"  pose: {_pose_words(d['camera'])}")
    if d.get("lens_tiles"):  # the spec alone would be the default tiles: another lens
        lines.append("  tiles, recorded in the file (the spec alone means other tiles: give the file itself as the "
                     "lens, --from/--to FILE):")
        lines += [f"    {words}" for words in d["lens_tiles"]]
    found = d.get("lens_metadata")
    if found:
        lines.append(f"  lens in metadata: {found['found']}")
        if found["profile"] or found["problem"]:
            lines.append(f"    lensfun:auto uses {found['profile']}" if found["profile"]
                         else f"    lensfun:auto: {found['problem']}")
        if found.get("exif"):  # the pinhole of the photo's focal length: lensfun's profile, where found, is better
            better = ("; lensfun:auto is the better choice: it also corrects the lens's distortion"
                      if found["profile"] else "")
            lines.append(f"    --from exif gives {found['exif']}{better}")
        elif found.get("exif_problem"):
            lines.append(f"    --from exif: {found['exif_problem']}")
    if d.get("st_map_upside_down"):
        name, (s, t) = d["file"], d["channels"][:2]
        lines.append(f"  looks like an ST map ({s} and {t} within [0, 1], monotone along rows and columns) but for its "
                     f"{t}, which grows down the image (y / H, as a remap grid normalised in OpenCV's rows): --stmap "
                     f"reads it as Nuke's t = 1 - y / H, so the warp by {name} would come out upside down; store "
                     f"1 - {t} in it first")
    elif d.get("looks_like_st_map"):
        name = d["file"]
        lines.append(f"  looks like an ST map ({' and '.join(d['channels'][:2])} within [0, 1], monotone along rows and "
                     f"columns); give --stmap {name} to use it (lenslab warp IMAGE --stmap {name}); its statistics "
                     "above are of the file read as a picture")
    lines += _structure_lines(d)
    if set(d.get("structure") or {}) <= {"file_bytes"}:  # no structure probe: the reader's attributes
        for k, v in d["attributes"].items():
            lines.append(f"  {k}: {v}")
    elif "icc" in d["attributes"]:  # what was done with an embedded profile (TIFF), which no probe shows
        lines.append(f"  icc: {d['attributes']['icc']}")
    return "\n".join(lines)


def _json_safe(value):
    """NaN and infinities (not valid JSON) become strings."""
    import math

    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def run(args: argparse.Namespace) -> int:
    from lenslab.errors import LenslabError

    if args.formats:
        if args.json:
            from lenslab.io.registry import formats

            print(json.dumps([{**f.describe(), "write": written(f) == "yes"} for f in formats().values()], indent=2))
        else:
            print(formats_text())
        return 0
    if not args.files:
        from lenslab.errors import UsageError

        raise UsageError("give one or more files, or --formats")
    from lenslab.jobs.funnel import library_output_to_stderr, one_line

    results, failed = [], 0
    for path in args.files:
        try:
            with library_output_to_stderr():  # what a codec prints of a damaged file stays out of the report
                d = describe(path, raw=args.raw, data_window=args.data_window)
        except (LenslabError, OSError) as exc:
            failed += 1
            print(f"lenslab info: error: {one_line(exc)}", file=sys.stderr)
            if args.json:
                results.append({"file": path, "error": one_line(exc)})
            continue
        if args.json:
            results.append(d)
        else:
            print(_video_text(d) if "video" in d else _text(d))
    if args.json:
        print(json.dumps(_json_safe(results), indent=2, allow_nan=False, default=str))
    if failed and len(args.files) > 1:  # (one file: its one error line says all)
        print(f"lenslab info: {failed} of {len(args.files)} files could not be read", file=sys.stderr)
    return 1 if failed else 0
