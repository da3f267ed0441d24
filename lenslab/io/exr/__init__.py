"""OpenEXR through the official ``OpenEXR`` bindings.

Reading
- Selects a part of a multipart file (``file.exr:2`` or ``file.exr:rgba_left``) and a layer
  (``file.exr:left`` reads ``left.R``, ``left.G``, ... ; ``file.exr:2:left`` both); without a
  selector: the first part (with a :class:`MultiPartWarning` naming the others, as a command's note), and
  its base (undotted) channels.
- A view of a multi-view part (``file.exr:right``, a name of its ``multiView`` attribute; the first is the
  default view, whose channels carry no view in their names, as OpenEXR names them) is read alone: its
  other channels are the extra channels, named without the view (``right.Z`` -> ``Z``), and the other
  views' channels are only named (``meta["other_views"]``), so a writer makes a plain image of the view.
- Channels become R, G, B (+ A); Y (+ A); luminance-chroma Y, RY, BY (+ A), converted to RGB; a lone
  channel of any name becomes a one-channel image; any other set is stacked in name order. Only a
  channel named ``A`` is alpha (as in OpenImageIO): ``u, v`` or ``forward.u, forward.v`` are two data
  channels. ``meta["channel_names"]`` keeps the file's names (a part's only layer included), which
  :func:`lenslab.io.output_channels` gives back to an EXR writer.
- Luminance-chroma: the subsampled chroma is upsampled (linear interpolation between the stored
  samples, which sit on even pixel coordinates) and ``R = (RY + 1) Y``, ``B = (BY + 1) Y``,
  ``G = (Y - wR R - wB B) / wG`` with the luminance weights of the file's chromaticities.
- Colour with a ``chromaticities`` attribute other than Rec.709 is converted to Rec.709 primaries
  (``rec709=False`` keeps the file's primaries).
- The data window is placed in the display window (outside it: 0, alpha 0) unless
  ``data_window=True`` keeps the stored pixels as they are.
- Tiled and mip-mapped files read at their full-resolution level. A deep part (scanlines or tiles) is flattened as a
  compositor flattens it (:mod:`lenslab.io.exr.deep`): one premultiplied RGBA pixel per pixel, ``Z`` the
  nearest sample's depth; ``meta["deep"]`` counts its samples.
- The first part's full-resolution channels are read a band of whole chunks at a time into the float32
  image (:mod:`lenslab.io.exr.bands`): no copy of the image at its stored type beside it. Other parts,
  subsampled and luminance-chroma channels take OpenEXR's whole-file read (:mod:`lenslab.io.exr.whole`).

Writing: half (default) or float, ZIP compression by default, the camera as a TOML string attribute
``lenslab.camera``. Half floats are made by :mod:`lenslab.io.halves`, as a half TIFF's are: values beyond
half's range are clamped to +-65504 and counted in a :class:`HalfOverflowWarning`; infinities and NaN are kept.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError, cause, clip
from lenslab.inputs.limits import check_size
from lenslab.io.exr.colour import REC709, luminance_weights, primary_matrix, upsample, yca_to_rgb  # noqa: F401
from lenslab.io.exr.keep import PartHeader
from lenslab.io.exr.select import (channel_names, find_part, image_types, layer_channels, part_label, parts_listing,
                                   select_channels, split_part_layer, view_of, views, without_view)
from lenslab.io.halves import HalfOverflowWarning, to_half  # noqa: F401 (the note, as lenslab.io names it)
from lenslab.library_output import library_call, quiet_library

CAMERA_ATTRIBUTE = "lenslab.camera"
COMPRESSIONS = ("none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab", "zstd", "htj2k256",
                "htj2k32")
_RESERVED = {"channels", "compression", "dataWindow", "displayWindow", "lineOrder", "type", "tiles", "name",
             "version", "chunkCount"}
#: attributes of OpenEXR's standard header given as plain values (a list from ``meta["attributes"]``)
_AS_TYPE = {"pixelAspectRatio": float, "screenWindowWidth": float,
            "screenWindowCenter": lambda v: np.asarray(v, np.float32).reshape(2)}


#: threads the OpenEXR codec may use per file, decoding and compressing (the bindings default to none; 0 = in the
#: calling thread); batch conversion with several worker processes sets it to 0 in each
THREADS = os.cpu_count() or 1


class MultiPartWarning(UserWarning):
    """A multi-part EXR read without a selector: its first part is read, and the note names the others.
    ``command_line`` is the note without the path (a command's note names the file)."""


def _first_part_note(path, parts) -> None:
    names = [p.name() for p in parts]
    rest = len(parts) - 1
    note = (f"has {len(parts)} parts ({parts_listing(names)}); read {part_label(0, names[0])} only: the other "
            f"{f'{rest} parts are' if rest > 1 else 'part is'} neither read nor written; pick another as "
            f"{Path(path).name}:NAME or {Path(path).name}:INDEX")
    warning = MultiPartWarning(f"{path}: {note}")
    warning.command_line = note
    warnings.warn(warning, stacklevel=4)


def plain_value(value):
    """Header attribute -> plain Python (lists, numbers, strings) for meta and JSON."""
    if isinstance(value, np.ndarray):  # (a double attribute: the bindings' 1-element float64 array, a number)
        return float(value[0]) if value.shape == (1,) and value.dtype == np.float64 else value.tolist()
    if isinstance(value, (tuple, list)):
        return [plain_value(v) for v in value]
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, (np.integer, np.floating)):
        return value.item()
    try:
        if hasattr(value, "name") and isinstance(getattr(value, "name"), str):  # enums
            return value.name
        return repr(value)
    except Exception:  # an attribute of a type the bindings do not know, whose bytes they cannot even show
        return f"<{type(value).__name__}>"


def read_exr(path: Path, selector: str | None = None, data_window: bool = False,
             rec709: bool = True, extra_channels: bool = False, layout=None) -> tuple[np.ndarray, dict]:
    """``layout``: the header as :func:`lenslab.io.exr.chunks.parse_header` read it (the byte budget's
    reading, given back by :func:`lenslab.io.read`); None: it is read here."""
    import OpenEXR

    from lenslab.io.exr.chunks import check_chunks, parse_header

    part_sel, layer_sel = split_part_layer(selector)
    layout = parse_header(path) if layout is None else layout
    check_chunks(path, layout)  # a truncated file: one line here, not the library's several on stderr
    parts = library_call(path, lambda: OpenEXR.File(str(path), header_only=True).parts,
                         "OpenEXR cannot read the header")
    if not parts:
        raise FormatError(f"{path}: OpenEXR found no readable part; the file is truncated or damaged")
    index, layer = find_part(path, parts, part_sel, layer_sel)
    hpart = parts[index]
    storage = plain_value(hpart.type())
    deep = "deep" in str(storage).lower()  # flattened as a compositor does (lenslab.io.exr.deep)
    if not selector and len(parts) > 1:
        _first_part_note(path, parts)
    for p in parts:
        (dx0, dy0), (dx1, dy1) = (tuple(int(v) for v in a) for a in p.header["dataWindow"])
        check_size(path, dx1 - dx0 + 1, dy1 - dy0 + 1)
    header = hpart.header
    (x0, y0), (x1, y1) = (tuple(int(v) for v in a) for a in header["dataWindow"])
    (X0, Y0), (X1, Y1) = (tuple(int(v) for v in a) for a in header["displayWindow"])
    check_size(path, X1 - X0 + 1, Y1 - Y0 + 1)
    names = channel_names(hpart)
    all_views = views(header)
    view = layer if layer in all_views else None  # one view of a multi-view part: its channels only
    if view is not None and not any(n.startswith(view + ".") for n in names):
        layer = None  # the default view: the undotted channels
    short = layer_channels(path, names, layer)
    sampling = {c.name: (c.xSampling, c.ySampling) for c in header.get("channels", [])}

    chroma = header.get("chromaticities")
    keys = set(short)
    order, out_names, ignored, converted = select_channels(keys)
    window, display = (x0, y0, x1, y1), (X0, Y0, X1, Y1)
    if not data_window:
        from lenslab.io.exr.whole import note_data_outside

        note_data_outside(path, window, display)
    if chroma is not None and (converted or rec709 and out_names[:3] == ["R", "G", "B"]):
        from lenslab.io.colour.primaries import check_chromaticities

        check_chromaticities(path, chroma)  # before any pixel is decoded
    used = {short.get(n, n) for n in out_names} | ({short[c] for c in ("Y", "RY", "BY") if c in short} if converted
                                                   else set())
    from lenslab.io.exr import bands
    from lenslab.io.exr.extra import extra_names, extra_planes

    others = [n for n in extra_names(names, used) if not (deep and n == "ZBack")]  # (deep: Z is the front depth)
    other_views = [n for n in others if view is not None and view_of(n, all_views) != view]
    others = [n for n in others if n not in other_views]
    wanted = others if extra_channels else []  # the extra planes come from the image's own decoding
    image_names = [short[c] for c in order if c is not None]
    deep_info = None
    if deep:
        from lenslab.io.exr.deep import read_deep
        from lenslab.io.exr.whole import placed

        if converted:
            raise FormatError(f"{path}: part {index} is a deep luminance-chroma image; lenslab flattens deep RGB, "
                              "grey and data channels only")
        image, pixel_types, planes, deep_info = read_deep(path, index, names, short, order, window, THREADS,
                                                          wanted, layout.parts[index].get("channel_types", {}))
        if not data_window and window != display:
            image = placed(image, window, display)
            planes = {n: placed(p, window, display) for n, p in planes.items()}
    elif not converted and bands.can_read(index, image_names + wanted, sampling):
        image, pixel_types, planes = bands.read_image(path, header, short, order, window, display, data_window,
                                                      THREADS, layout.parts[0].get("channel_types", {}), wanted)
    else:
        from lenslab.io.exr.whole import placed, read_whole

        image, pixel_types, chans = read_whole(path, index, header, names, short, order, converted, sampling,
                                               window, THREADS)
        if not data_window and window != display:
            image = placed(image, window, display)
        planes = extra_planes(path, chans, wanted, sampling, window, None if data_window else display)
    if view is not None:  # the view's own channels, named as a plain image's (left.Z -> Z)
        planes = {without_view(n, view): plane for n, plane in planes.items()}

    primaries_converted, gamut = False, None
    if rec709 and chroma is not None and out_names[:3] == ["R", "G", "B"] and \
            not np.allclose(np.asarray(chroma, dtype=np.float64), REC709, atol=1e-4):
        from lenslab.io.colour.gamut import negative_pixels, widens
        from lenslab.io.colour.primaries import matrix_from_chromaticities, to_rec709

        matrix = matrix_from_chromaticities(chroma)
        # wider primaries, no negative of the file's own: the negatives after the conversion are colours outside
        # Rec.709's gamut
        gamut = "chromaticities" if widens(matrix) and negative_pixels(image) == 0 else None
        to_rec709(image, matrix)  # file RGB -> XYZ -> Rec.709, by bands
        primaries_converted = True

    stored = image_types(order, short, pixel_types, converted)
    pixel_types = set(stored) or set(pixel_types.values())
    bits = 32 if ({"FLOAT", "UINT"} & pixel_types) else 16
    attributes = {k: plain_value(v) for k, v in header.items() if k != "channels"}
    meta = {
        "format": "exr",
        "bit_depth": bits,
        "sample_type": "float" if pixel_types <= {"FLOAT"} else ("half" if pixel_types <= {"HALF"} else
                                                              "/".join(sorted(t.lower() for t in pixel_types))),
        "channels": out_names,
        # each image channel's stored type (half, float or uint): what an EXR writer keeps
        "channel_types": [t.lower() for t in stored],
        # the names a writer keeps (EXR): the file's own, with the layer of a part's only layer
        "channel_names": out_names if converted or layer is not None else [short.get(n, n) for n in out_names],
        "display_encoded": False,
        "attributes": attributes,
        "part": index,
        "part_name": hpart.name(),
        "parts": [p.name() for p in parts],
        "layer": layer,
        "file_channels": names,
        "ignored_channels": [short[c] for c in ignored],
        # every channel of the part not in the image (Z, N.x, other layers), and with extra_channels=True
        # their planes (stored type, placed as the image is) for an EXR writer's ``extra``
        "extra_channels": others,
        "extra_planes": planes,
        # a view of a multi-view part read alone: its name, and the other views' channels (not read)
        "view": view,
        "other_views": other_views,
        "luminance_chroma": converted,
        "primaries_converted_to_rec709": primaries_converted,
        "data_window": [x0, y0, x1, y1],
        "display_window": [X0, Y0, X1, Y1],
        "origin": [x0, y0] if data_window else [X0, Y0],
        "storage": storage,
        # a deep part: its samples (total, most in one pixel) and what flattening them counted
        "deep": deep_info,
        # the part's header as OpenEXR read it (raw values): what an EXR writer keeps of it
        # (:func:`lenslab.io.exr.keep.kept_header`) without reading the file again
        "exr_header": PartHeader(header),
    }
    if gamut:
        meta["wide_gamut"] = gamut  # what gave the wide primaries (lenslab.io.colour.gamut.WIDE_GAMUT)
    return image, meta


def _planes(image: np.ndarray, kinds: list[str]) -> list[np.ndarray]:
    """Each channel of a float32 ``H x W x C`` image as a contiguous plane of its EXR pixel type: half
    (clamped as :func:`lenslab.io.halves.to_half` does, in one call for every half channel: one note), float, or uint
    (rounded, clipped to 0 .. 2**32 - 1, NaN as 0)."""
    halves = [i for i, k in enumerate(kinds) if k == "half"]
    half = to_half(image[..., halves]) if halves else None
    out = []
    for i, kind in enumerate(kinds):
        plane = image[..., i]
        if kind == "half":
            out.append(np.ascontiguousarray(half[..., halves.index(i)]))
        elif kind == "uint":
            out.append(np.nan_to_num(np.clip(np.rint(plane.astype(np.float64)), 0, 2 ** 32 - 1)).astype(np.uint32))
        else:
            out.append(np.ascontiguousarray(plane, np.float32))
    return out


def write_exr(tmp: Path, image: np.ndarray, pixel_type: str | list[str] = "half", compression: str = "zip",
              channels: list[str] | None = None, attributes: dict | None = None, camera=None,
              threads: int | None = None, in_place: bool = False, extra: dict | None = None,
              window=None) -> None:
    """Write ``image`` (float32 ``H x W x C``) to ``tmp``; ``pixel_type``: "half" or "float" for every
    channel, or a list of "half", "float", "uint", one a channel (an EXR's channels as they were stored);
    ``in_place``: a half-float file is converted in the image's own memory, which the caller gives up
    (``image`` is overwritten). ``window``: the data and display windows ``(x0, y0, x1, y1)`` (default:
    both the image's own size at 0, 0). ``extra``: more channels
    ``{name: H x W plane}`` (depth, normals...) written in their own type (half, float32 or uint32)."""
    import OpenEXR

    h, w, c = image.shape
    per_channel = not isinstance(pixel_type, str)
    kinds = list(pixel_type) if per_channel else [pixel_type] * c
    if len(kinds) != c or any(k not in ("half", "float", "uint") for k in kinds) or \
            (not per_channel and pixel_type == "uint"):
        raise FormatError(f"EXR pixel_type must be 'half' or 'float', or one of 'half', 'float', 'uint' for each "
                          f"of the {c} channels, not {clip(pixel_type)}")
    comp = str(compression).lower().replace("_compression", "")
    if comp not in COMPRESSIONS:
        raise FormatError(f"unknown EXR compression {compression!r}; choose one of {', '.join(COMPRESSIONS)} "
                          "(zip is the most widely readable)")
    if channels is None:
        from lenslab.io import DEFAULT_CHANNELS

        channels = DEFAULT_CHANNELS.get(c)
        if channels is None:
            raise FormatError(f"an image with {c} channels needs channel names: pass channels=[...]")
    if len(channels) != c:
        raise FormatError(f"{len(channels)} channel names given for an image with {c} channels")
    if len(set(kinds)) == 1 and kinds[0] != "uint":
        data = to_half(image, in_place=in_place) if kinds[0] == "half" else np.asarray(image, np.float32)
    else:  # each channel in its own type (an EXR's colour as it was stored): one plane at a time
        data = _planes(image, kinds)
    enum = "NO_COMPRESSION" if comp == "none" else f"{comp.upper()}_COMPRESSION"
    header = {"compression": getattr(OpenEXR, enum), "type": OpenEXR.scanlineimage}
    for k, v in (attributes or {}).items():
        if k in _RESERVED:
            continue
        try:
            header[k] = _AS_TYPE[k](v) if k in _AS_TYPE else v
        except (TypeError, ValueError):
            raise FormatError(f"EXR attribute {k}: {clip(v)} is not a {'pair of numbers' if 'Center' in k else 'number'}") from None
    if window is not None:  # the stored pixels' place: (x0, y0, x1, y1) of the data and display windows
        (x0, y0, x1, y1), (X0, Y0, X1, Y1) = (tuple(int(v) for v in box) for box in window)
        if (x1 - x0 + 1, y1 - y0 + 1) != (w, h) or X1 < X0 or Y1 < Y0:
            raise FormatError(f"EXR data window {x1 - x0 + 1} x {y1 - y0 + 1} given for an image of {w} x {h}")
        header["dataWindow"] = (np.array([x0, y0], np.int32), np.array([x1, y1], np.int32))
        header["displayWindow"] = (np.array([X0, Y0], np.int32), np.array([X1, Y1], np.int32))
    if camera is not None:
        header[CAMERA_ATTRIBUTE] = camera.to_toml()
    if isinstance(data, list):
        chans = dict(zip(channels, data))
    elif "".join(channels) in ("RGB", "RGBA"):  # one interleaved array: the bindings split it without a copy
        chans = {"".join(channels): np.ascontiguousarray(data)}
    else:  # the bindings need each channel contiguous (they write strided arrays wrongly)
        from lenslab.io.exr.planes import planes_after

        chans = dict(zip(channels, planes_after(data, image) if in_place else
                         (np.ascontiguousarray(data[..., i]) for i in range(c))))
    for name, plane in (extra or {}).items():
        if name in channels or name in chans:
            continue  # a channel of the image itself
        if plane.shape != (h, w):
            raise FormatError(f"channel {clip(name)} is {plane.shape[1]} x {plane.shape[0]}, not the image's {w} x {h}")
        chans[name] = np.ascontiguousarray(plane if plane.dtype in (np.float16, np.float32, np.uint32)
                                           else plane.astype(np.float32))
    threads = THREADS if threads is None else int(threads)
    if OpenEXR.global_thread_count() != threads:  # the bindings compress on OpenEXR's global pool: the
        OpenEXR.set_global_thread_count(threads)  # File's own count reaches reading only
    try:
        with quiet_library():
            OpenEXR.File(header, chans, threads).write(str(tmp))
    except (TypeError, ValueError, RuntimeError) as exc:
        raise FormatError(f"OpenEXR could not write the image ({cause(exc)})") from None
