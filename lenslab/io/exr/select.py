"""Which part, layer and channels of an EXR an image is read from: the selector (``file.exr:2:left``),
the part's channel names, a layer's short names, the channels that make the image (alpha last) and
their stored types."""

from __future__ import annotations

from lenslab.errors import FormatError, clip


def part_name(name) -> str:
    """A part's name as users read it in notes and errors: quoted, or ``unnamed`` (a single-part file's part)."""
    return clip(name) if name else "unnamed"


def part_label(index: int, name) -> str:
    """``part 2 ('rgba_left')``, ``part 0 (unnamed)``."""
    return f"part {index} ({part_name(name)})"


#: parts an error names: every part of a real file (the names the user may type), a bound for a hostile one
ERROR_PARTS = 100


def parts_listing(names, limit: int = 8) -> str:
    """``0: 'rgba_right', 1: 'depth_left' and 8 more``: the parts of a file, as its notes list them (errors
    give :data:`ERROR_PARTS`)."""
    return ", ".join(f"{i}: {part_name(n)}" for i, n in enumerate(names[:limit])) + (
        f" and {len(names) - limit} more" if len(names) > limit else "")


def split_part_layer(selector: str | None) -> tuple[str | None, str | None]:
    if not selector:
        return None, None
    if ":" in selector:
        part, layer = selector.split(":", 1)
        return part or None, layer or None
    return selector, None


def find_part(path, parts, part_sel: str | None, layer_sel: str | None):
    """(part index, layer) for the selector; a lone selector is a part index, a part name, a layer or view of
    a part, or the view of the only part that carries it (the ``view`` attribute of a multi-part file's part)."""
    names = [p.name() for p in parts]
    if part_sel is None:
        return 0, layer_sel
    if part_sel.isdigit():
        i = int(part_sel)
        if i >= len(parts):
            raise FormatError(f"{path}: part {i} does not exist; the file has {len(parts)} part(s) "
                              f"({parts_listing(names, ERROR_PARTS)})")
        return i, layer_sel
    if part_sel in names:
        return names.index(part_sel), layer_sel
    if layer_sel is None:  # a lone name that is not a part: a layer (or view) of the first part with it
        for i, p in enumerate(parts):
            if any(c.startswith(part_sel + ".") for c in channel_names(p)) or part_sel in views(p.header):
                return i, part_sel
        # the one part of a multi-part stereo file whose ``view`` attribute is the name (rgba.left: left)
        viewed = [i for i, p in enumerate(parts) if isinstance(p.header, dict) and p.header.get("view") == part_sel]
        if len(viewed) == 1:
            return viewed[0], None
    layers = sorted({c.rsplit(".", 1)[0] for p in parts for c in channel_names(p) if "." in c})
    known = list(dict.fromkeys(v for p in parts for v in views(p.header)))  # a selector takes a view too
    raise FormatError(f"{path}: no part, layer or view named {part_sel!r}; parts: {parts_listing(names, ERROR_PARTS)}; layers: "
                      f"{', '.join(layers) or 'none'}" + (f"; views: {', '.join(known)}" if known else ""))


def views(header) -> list[str]:
    """The views of a multi-view part (its ``multiView`` attribute; the first is the default view), or []."""
    return [str(v) for v in (header.get("multiView") or [])] if isinstance(header, dict) else []


def view_of(name: str, names: list[str]) -> str:
    """The view channel ``name`` belongs to among views ``names``, by OpenEXR's naming of multi-view
    channels: the name's second-to-last component when it is a view (``left.R``, ``diffuse.left.R``),
    else the first, default, view (``R``, ``diffuse.R``)."""
    parts = name.split(".")
    return parts[-2] if len(parts) >= 2 and parts[-2] in names else names[0]


def without_view(name: str, view: str) -> str:
    """A channel's name with its view left out (``left.Z`` -> ``Z``, ``depth.left.Z`` -> ``depth.Z``)."""
    parts = name.split(".")
    if len(parts) >= 2 and parts[-2] == view:
        del parts[-2]
    return ".".join(parts)


def channel_names(part) -> list[str]:
    chans = part.header.get("channels") if isinstance(part.header, dict) else None
    if chans is None:
        return list(part.channels)
    return [c.name for c in chans]


def layer_channels(path, names: list[str], layer: str | None) -> dict[str, str]:
    """Short name -> full channel name for ``layer`` (None: the base layer, or the only layer)."""
    if layer is not None:
        sel = {n[len(layer) + 1:]: n for n in names if n.startswith(layer + ".") and "." not in n[len(layer) + 1:]}
        if not sel:
            raise FormatError(f"{path}: no channels in layer {layer!r}; channels: {clip(', '.join(names), 80)}")
        return sel
    base = {n: n for n in names if "." not in n}
    if base:
        return base
    layers = sorted({n.rsplit(".", 1)[0] for n in names})
    if len(layers) == 1:
        return {n.rsplit(".", 1)[1]: n for n in names}
    raise FormatError(f"{path}: the part has no base channels, only layers {', '.join(layers)}; "
                      f"choose one as 'file.exr:LAYER'")


def image_types(order: list[str | None], short: dict[str, str], types: dict[str, str], converted: bool) -> list[str]:
    """The stored type (HALF, FLOAT, UINT) of each channel of the image read in ``order``: a missing colour
    channel (None) takes its neighbours' type; R, G, B made from luminance-chroma take Y's."""
    known = [types.get(short[c], "UNKNOWN") if c is not None else None for c in order]
    if converted:
        known[1] = known[2] = known[0]
    fill = next((t for t in known if t is not None), "HALF")
    return [fill if t is None else t for t in known]


def select_channels(keys: set[str]) -> tuple[list[str | None], list[str], list[str], bool]:
    """(channels to read in the image's order, by short name; None: a missing colour channel, 0),
    the image's channel names, the channels left out, and whether the file is luminance-chroma
    (Y, RY, BY: read and converted to RGB)."""
    alpha = ["A"] if "A" in keys else []
    if len(keys) == 1:  # a lone channel of any name (e.g. only 'G', or 'Z') is a one-channel image
        return list(keys), list(keys), [], False
    if keys & {"R", "G", "B"}:
        return [c if c in keys else None for c in "RGB"] + alpha, ["R", "G", "B"] + alpha, \
            sorted(keys - {"R", "G", "B", "A"}), False
    if "Y" in keys:
        ignored = sorted(keys - {"Y", "RY", "BY", "A"})
        if "RY" in keys and "BY" in keys:
            return ["Y", "RY", "BY"] + alpha, ["R", "G", "B"] + alpha, ignored, True
        return ["Y"] + alpha, ["Y"] + alpha, ignored, False  # grey (and alpha, as OpenImageIO reads them)
    order = sorted(keys - {"A"}) + alpha  # alpha last, as in memory
    return order, list(order), [], False
