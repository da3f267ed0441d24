"""OpenEXR: linear half/float/uint channels, parts, layers, any compression (codec: :mod:`lenslab.io.exr`)."""

from __future__ import annotations

from lenslab.io.plugin import Format


def _read(path, selector=None, data_window=False, rec709=True, extra_channels=False, parsed=None):
    from lenslab.io.exr import read_exr

    return read_exr(path, selector, data_window=data_window, rec709=rec709, extra_channels=extra_channels,
                    layout=parsed)


def _write(tmp, image, exif=None, **options):
    from lenslab.io.exr import write_exr

    if exif:  # camera tags as header attributes, under OpenImageIO's names
        from lenslab.exif_tags import exr_attributes

        options["attributes"] = {**(options.get("attributes") or {}), **exr_attributes(exif)}

    write_exr(tmp, image, **options)


def _declare(path, **options):
    from lenslab.io.exr.chunks import declare_exr

    return declare_exr(path, **options)


def _channel_names(path) -> list[str]:
    from lenslab.io.exr.chunks import first_part_channels

    return first_part_channels(path)


def _window(w) -> list[int]:
    (x0, y0), (x1, y1) = w
    return [int(x0), int(y0), int(x1), int(y1)]


def _probe(path) -> dict:
    """Every part: storage, compression, windows, line order, channels (pixel type, sampling), layers,
    attributes, and a deep part's sample counts (``deep_samples``: total, most in one pixel, pixels with
    any). Channel types come from lenslab's own reading of the header (no pixel is decoded; OpenEXR's
    header-only reading does not give them)."""
    import OpenEXR

    from lenslab.io.exr import plain_value
    from lenslab.io.exr.chunks import parse_header
    from lenslab.library_output import library_call

    from lenslab.io.exr.deep_counts import deep_counts

    head = library_call(path, lambda: OpenEXR.File(str(path), header_only=True), "OpenEXR cannot read the header")
    layout = parse_header(path)
    types = {(i, name): kind.lower() for i, part in enumerate(layout.parts)
             for name, kind in part.get("channel_types", {}).items()}
    samples = deep_counts(path, layout)  # each deep part's sample counts, from its tables
    parts = []
    for i, part in enumerate(head.parts):
        h = part.header
        chans = [{"name": c.name, "type": types.get((i, c.name), "unknown"),
                  "sampling": [int(c.xSampling), int(c.ySampling)], "linear": bool(c.pLinear)}
                 for c in h.get("channels", [])]
        parts.append({
            "index": i,
            "name": h.get("name"),
            "storage": str(h.get("type", "scanlineimage")).split(".")[-1],
            "compression": str(h.get("compression", "")).split(".")[-1].replace("_COMPRESSION", "").lower(),
            "data_window": _window(h["dataWindow"]),
            "display_window": _window(h["displayWindow"]),
            "line_order": str(h.get("lineOrder", "")).split(".")[-1].lower(),
            "channels": chans,
            "layers": sorted({c["name"].rsplit(".", 1)[0] for c in chans if "." in c["name"]}),
            "attributes": {k: plain_value(v) for k, v in h.items()
                           if k not in ("channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                                        "name", "type")},
        })
        if i in samples:
            parts[-1]["deep_samples"] = {"total": samples[i].total, "max_per_pixel": samples[i].max_per_pixel,
                                         "pixels": samples[i].pixels}
        if "tiles" in h:  # in the words convert's note uses, not the bindings' repr
            from lenslab.io.exr.keep import tiling

            parts[-1]["attributes"]["tiles"] = tiling(h["tiles"], parts[-1]["data_window"])[0]
    return {"parts": parts}


FORMATS = (Format(
    name="exr", title="OpenEXR", extensions=(".exr",), magic=lambda head: head.startswith(b"\x76\x2f\x31\x01"),
    hdr=True, alpha=True, channels=(1, 2, 3, 4), bit_depths=(16, 32), sample_types=("half", "float", "uint"),
    written_types=("half", "float"),
    read=_read, declare=_declare, write=_write, probe=_probe, channel_names=_channel_names,
    read_options=("data_window", "rec709", "extra_channels"),
    write_options={"pixel_type": "half or float (default half)",
                   "compression": "zip (default), piz, zips, rle, none, pxr24, b44, b44a, dwaa, dwab, zstd, ...",
                   "channels": "channel names, for images that are not Y, RGB or RGBA",
                   "attributes": "header attributes {name: value}",
                   "exif": "camera tags {name: value} (lenslab.io.exif) under OpenImageIO's names",
                   "extra": "more channels {name: H x W plane} (depth, normals...), written in their own type",
                   "window": "(data window, display window), each (x0, y0, x1, y1): where the pixels lie "
                             "(default: both the image, at 0, 0)",
                   "threads": "codec threads (default: one per core)",
                   "in_place": "True: a half-float file is converted in the image's own memory (the array is "
                               "overwritten; saves a copy of half the image's size)"},
    selectors=True, camera=True,
    compressions=("none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab", "zstd", "htj2k256",
                  "htj2k32"),
    note="multi-part and layered files; luminance/chroma and other primaries converted to Rec.709; deep "
         "parts flattened (sorted by depth, composited with over)"),)
