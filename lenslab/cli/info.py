"""Print what image files hold: format, size, channels, sample type, per-channel min/mean/max (over
finite values), counts of NaN, infinite and negative values, and the lens model if the file carries
a camera (EXR files written by lenslab do).

EXR selectors work here too: 'file.exr:left' (a layer), 'file.exr:2' or 'file.exr:NAME' (a part).

examples:
  lenslab info pano.exr
  lenslab info --json renders/*.exr > stats.json
"""

from __future__ import annotations

import argparse
import json
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE", help="image files (EXR, PFM, PPM/PGM/PBM, JPG, PNG)")
    parser.add_argument("--json", action="store_true", help="print one JSON list with an object per file")
    parser.add_argument("--raw", action="store_true",
                        help="statistics of the stored code values (scaled to 0..1) instead of linear light")
    parser.add_argument("--data-window", action="store_true",
                        help="EXR: statistics of the stored data window, not the display window")


def describe(path: str, raw: bool = False, data_window: bool = False) -> dict:
    """Everything ``info`` prints about one file, as a JSON-ready dict."""
    import numpy as np

    from lenslab.io import read

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
    }
    for key in ("part", "part_name", "layer", "data_window", "display_window", "ignored_channels",
                "luminance_chroma", "primaries_converted_to_rec709"):
        if key in meta:
            out[key] = meta[key]
    attrs = {k: v for k, v in meta["attributes"].items() if k != "lenslab.camera"}
    out["attributes"] = attrs
    return out


def _text(d: dict) -> str:
    lines = [f"{d['file']}: {d['format'].upper()} {d['width']} x {d['height']}, {len(d['channels'])} channel(s) "
             f"{','.join(d['channels'])}, {d['sample_type']} {d['bit_depth']}-bit"
             f"{', sRGB-decoded to linear' if d['display_encoded'] else ''}"]
    if d.get("part_name") is not None and d.get("format") == "exr":
        extra = f"  part {d['part']}"
        if d["part_name"]:
            extra += f" ({d['part_name']})"
        if d.get("layer"):
            extra += f", layer {d['layer']}"
        if d.get("data_window") != d.get("display_window"):
            extra += f", data window {d['data_window']} in display window {d['display_window']}"
        lines.append(extra)
    if d.get("luminance_chroma"):
        lines.append("  luminance/chroma (Y, RY, BY) converted to RGB")
    if d.get("primaries_converted_to_rec709"):
        lines.append("  colour converted from the file's chromaticities to Rec.709 primaries")
    if d.get("ignored_channels"):
        lines.append(f"  other channels (not read): {', '.join(d['ignored_channels'])}")
    lines.append(f"  {'channel':<8s} {'min':>12s} {'mean':>12s} {'max':>12s} {'NaN':>8s} {'inf':>8s} {'negative':>9s}")

    def num(v):
        return f"{v:12.6g}" if v is not None else f"{'-':>12s}"

    for s in d["stats"]:
        lines.append(f"  {s['channel']:<8s} {num(s['min'])} {num(s['mean'])} {num(s['max'])} "
                     f"{s['nan']:8d} {s['inf']:8d} {s['negative']:9d}")
    lines.append(f"  lens: {d['lens']}" if d["lens"] else "  lens: none stored")
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

    results, failed = [], 0
    for path in args.files:
        try:
            d = describe(path, raw=args.raw, data_window=args.data_window)
        except (LenslabError, OSError) as exc:
            failed += 1
            print(f"lenslab info: error: {exc}", file=sys.stderr)
            if args.json:
                results.append({"file": path, "error": str(exc)})
            continue
        if args.json:
            results.append(d)
        else:
            print(_text(d))
    if args.json:
        print(json.dumps(_json_safe(results), indent=2, allow_nan=False, default=str))
    if failed:
        print(f"lenslab info: {failed} of {len(args.files)} files could not be read", file=sys.stderr)
    return 1 if failed else 0
