"""What a file holds beyond the pixels ``read`` returns: every EXR part, layer and channel (pixel type,
sampling), compression, windows and attributes; TIFF pages; Radiance header; video streams.

``probe(path) -> dict`` (JSON-ready) never decodes more than it must: EXR channel types come from
OpenEXR's full read only because the bindings give them with the pixels.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from lenslab.errors import FormatError


def _window(w) -> list[int]:
    (x0, y0), (x1, y1) = w
    return [int(x0), int(y0), int(x1), int(y1)]


_EXR_TYPES = {"float16": "half", "float32": "float", "uint32": "uint"}


def _exr(path: Path) -> dict:
    import OpenEXR

    from lenslab.io.exr import plain_value

    try:
        head = OpenEXR.File(str(path), header_only=True)
    except Exception as exc:
        raise FormatError(f"{path}: OpenEXR cannot read the header ({exc}); the file is damaged") from None
    types: dict[tuple[int, str], str] = {}
    try:  # pixel types are only given with the pixels; deep files cannot be read so
        full = OpenEXR.File(str(path), separate_channels=True)
        for i, part in enumerate(full.parts):
            for name, ch in part.channels.items():
                types[(i, name)] = _EXR_TYPES.get(str(ch.pixels.dtype), str(ch.pixels.dtype))
    except Exception:
        pass
    parts = []
    for i, part in enumerate(head.parts):
        h = part.header
        chans = []
        for c in h.get("channels", []):
            chans.append({"name": c.name, "type": types.get((i, c.name), "unknown"),
                          "sampling": [int(c.xSampling), int(c.ySampling)], "linear": bool(c.pLinear)})
        layers = sorted({c["name"].rsplit(".", 1)[0] for c in chans if "." in c["name"]})
        storage = str(h.get("type", "scanlineimage")).split(".")[-1]
        parts.append({
            "index": i,
            "name": h.get("name"),
            "storage": storage,
            "compression": str(h.get("compression", "")).split(".")[-1].replace("_COMPRESSION", "").lower(),
            "data_window": _window(h["dataWindow"]),
            "display_window": _window(h["displayWindow"]),
            "line_order": str(h.get("lineOrder", "")).split(".")[-1].lower(),
            "channels": chans,
            "layers": layers,
            "attributes": {k: plain_value(v) for k, v in h.items()
                           if k not in ("channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                                        "name", "type")},
        })
    return {"parts": parts}


def _tiff(path: Path) -> dict:
    import tifffile

    with tifffile.TiffFile(path) as tif:
        pages = []
        for page in tif.pages:
            pages.append({"shape": list(page.shape), "axes": page.axes, "dtype": str(page.dtype),
                          "compression": page.compression.name.lower(), "photometric": page.photometric.name.lower(),
                          "planar": "separate" if int(page.planarconfig) == 2 else "contig",
                          "extrasamples": [int(v) for v in page.extrasamples]})
    return {"pages": pages}


def _hdr(path: Path) -> dict:
    from lenslab.io.rgbe import parse_header

    with open(path, "rb") as f:
        data = f.read(1 << 16)
    attrs, res, _ = parse_header(path, data)
    s1, a1, n1, s2, a2, n2 = res
    return {"header": attrs, "resolution": f"{s1.decode()}{a1.decode()} {n1} {s2.decode()}{a2.decode()} {n2}"}


# FFmpeg's colour enums (libavutil/pixfmt.h) by the names ffprobe prints
_PRIMARIES = {1: "bt709", 2: "unspecified", 5: "bt470bg", 6: "smpte170m", 9: "bt2020", 12: "smpte432 (P3-D65)"}
_TRANSFER = {1: "bt709", 2: "unspecified", 6: "smpte170m", 13: "iec61966-2-1 (sRGB)", 14: "bt2020-10",
             15: "bt2020-12", 16: "smpte2084 (PQ)", 18: "arib-std-b67 (HLG)"}
_MATRIX = {0: "gbr", 1: "bt709", 2: "unspecified", 5: "bt470bg", 6: "smpte170m", 9: "bt2020nc", 10: "bt2020c"}
_RANGE = {0: "unspecified", 1: "tv (limited)", 2: "pc (full)"}


def _tag(names: dict, value) -> str:
    return names.get(int(value), str(int(value)))


def video_streams(path: Path) -> dict:
    """Container, duration and every stream of a video file (PyAV)."""
    import av

    try:
        container = av.open(str(path))
    except av.error.FFmpegError as exc:
        raise FormatError(f"{path}: FFmpeg cannot open it as a video ({exc})") from None
    with container:
        streams = []
        for s in container.streams:
            d = {"index": s.index, "kind": s.type, "codec": s.codec_context.name}
            if s.type == "video":
                cc = s.codec_context
                d.update({"width": cc.width, "height": cc.height, "pixel_format": cc.pix_fmt,
                          "frame_rate": str(s.average_rate), "frames": int(s.frames),
                          "colour_primaries": _tag(_PRIMARIES, cc.color_primaries),
                          "transfer": _tag(_TRANSFER, cc.color_trc), "matrix": _tag(_MATRIX, cc.colorspace),
                          "range": _tag(_RANGE, cc.color_range)})
            elif s.type == "audio":
                d.update({"sample_rate": s.codec_context.sample_rate, "channels": s.codec_context.channels})
            streams.append(d)
        return {"container": container.format.name,
                "duration_s": None if container.duration is None else container.duration / 1e6,
                "streams": streams}


_PROBES = {"exr": _exr, "tiff": _tiff, "hdr": _hdr}


def probe(path: str | os.PathLike, fmt: str) -> dict[str, Any]:
    """The structure of an image file, as ``lenslab info`` shows it, without reading its pixels.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    fmt : str
        Its format, a name of ``lenslab info --formats`` (:func:`lenslab.io.sniff` tells it).

    Returns
    -------
    dict
        ``file_bytes``, and by format: EXR ``parts`` (each with its storage, compression, data and display
        windows, channels with their pixel types, layers and attributes), TIFF ``pages`` (shape, axes,
        dtype, compression, photometric, planar layout, extra samples), Radiance HDR ``header`` and
        ``resolution``. Other formats give ``file_bytes`` only.

    Raises
    ------
    lenslab.errors.FormatError
        A header the format's library cannot read.
    OSError
        A file that cannot be opened.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np, lenslab
    >>> from lenslab.io import sniff
    >>> from lenslab.io.probe import probe
    >>> path = lenslab.write(pathlib.Path(tempfile.mkdtemp()) / "a.exr", np.ones((2, 4, 3)), pixel_type="float")
    >>> part = probe(path, sniff(path))["parts"][0]
    >>> part["data_window"], [(c["name"], c["type"]) for c in part["channels"]]
    ([0, 0, 3, 1], [('B', 'float'), ('G', 'float'), ('R', 'float')])
    """
    p = Path(path)
    out = {"file_bytes": p.stat().st_size}
    fn = _PROBES.get(fmt)
    if fn is not None:
        out.update(fn(p))
    return out
