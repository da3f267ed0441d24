"""What an EXR written from an EXR keeps of the input's header, as a compositor (or ``oiiotool``) would.

- The data and display windows: the stored pixels are written where they were, outside the data window
  nothing (a reader gives 0 there, as for the input), so a depth ``Z`` is never given a 0 it did not have.
- Attributes that still describe the written channels: ``multiView`` when every view's channels are
  written under their own names (a layer read alone, ``file.exr:left``, becomes ``R, G, B``: the views
  no longer hold, the attribute is left out); a part's ``view``; ``chromaticities`` unless the colour was
  converted to Rec.709 on reading (the file then holds Rec.709, OpenEXR's default); everything about the
  shot and the file (``owner``, ``comments``, ``capDate``, ``envmap``, ``wrapmodes``, densities ...).
- Left out: what the writer sets itself (channels, compression, line order, storage, tiles, part name,
  chunk count): a tiled or mip-mapped input is written as scanlines, its full-resolution level only, and
  :func:`warn_scanlines` says so in one note, the preview image (a thumbnail of pixels that may have changed), lenslab's camera (the
  writer stores the camera read, if any), and values of types the bindings cannot write back.
"""

from __future__ import annotations


#: attributes the writer sets from the image or its options, never copied
WRITER_SETS = {"channels", "compression", "dataWindow", "displayWindow", "lineOrder", "type", "tiles", "name",
               "version", "chunkCount", "preview", "lenslab.camera"}


class PartHeader(dict):
    """A part's header as OpenEXR read it (``meta["exr_header"]``), which pickles (and deep-copies) as what
    can be pickled of it: the bindings cannot pickle some of their objects (channel lists, tile descriptions),
    and ``meta`` must travel (a Dask task's result) and copy as every other format's does. Left out of a copy:
    those values only (the writer sets them itself)."""

    def __reduce__(self):
        import pickle

        def portable(value) -> bool:
            try:
                pickle.dumps(value)
            except Exception:  # (the bindings raise TypeError; anything else is not portable either)
                return False
            return True

        return PartHeader, ({k: v for k, v in self.items() if portable(v)},)


def _views_hold(file_channels: list[str], written: set[str]) -> bool:
    """Whether every view's channels are written under their own names. Each channel belongs to a view (a
    prefix naming one, else the first, default view), so: every channel of the part."""
    return set(file_channels) <= written


def _writable(value) -> bool:
    import numpy as np

    if isinstance(value, (str, int, float, np.ndarray)):
        return True
    if isinstance(value, (list, tuple)):
        return all(_writable(v) for v in value)
    return type(value).__module__ == "OpenEXR"  # the bindings' own types (enums, rationals, time codes...)


def kept_header(meta: dict, written: list[str]) -> dict:
    """The write options that keep ``meta``'s part header (``meta``: what :func:`lenslab.io.read` gave for
    an EXR read with ``data_window=True``, its ``exr_header`` the part's header as OpenEXR read it then;
    ``written``: every channel name to be written): ``window`` (the data and display windows) and
    ``attributes`` (raw values of that header)."""
    header = meta.get("exr_header") or {}
    keep = {}
    for name, value in header.items():
        if name in WRITER_SETS or not _writable(value):
            continue
        if name == "chromaticities" and meta.get("primaries_converted_to_rec709"):
            continue
        if name == "multiView" and not _views_hold(meta.get("file_channels") or [], set(written)):
            continue
        keep[name] = value
    return {"window": (meta["data_window"], meta["display_window"]), "attributes": keep}


class ScanlineWarning(UserWarning):
    """A tiled (or mip-mapped) EXR was written from EXR as scanlines, its full-resolution level only.
    ``command_line`` is the note without the path (a command's note names the file)."""


def _levels(n: int, round_up: bool) -> int:
    """OpenEXR's level count along a side of ``n`` pixels: log2(n) rounded down (or up) plus one."""
    return ((n - 1).bit_length() if round_up else n.bit_length() - 1) + 1


def tiling(tiles, data_window) -> tuple[str, int]:
    """An EXR part's tiling in words ("64 x 64 tiles, mip-mapped, 7 levels"; "32 x 16 tiles" for one level) and
    its level count, from OpenEXR's ``TileDescription`` and the part's data window (x0, y0, x1, y1)."""
    x0, y0, x1, y1 = data_window
    up = "UP" in str(getattr(tiles, "roundingMode", ""))
    nx, ny = _levels(x1 - x0 + 1, up), _levels(y1 - y0 + 1, up)
    mode = str(getattr(tiles, "mode", ""))
    levels = max(nx, ny) if "MIPMAP" in mode else nx * ny if "RIPMAP" in mode else 1
    kind = "mip-mapped" if "MIPMAP" in mode else "rip-mapped"
    return f"{tiles.xSize} x {tiles.ySize} tiles" + (f", {kind}, {levels} levels" if levels > 1 else ""), levels


def storage_note(meta: dict) -> str | None:
    """What writing ``meta``'s EXR part as scanlines leaves out, in one line; None for a scanline part."""
    tiles = (meta.get("exr_header") or {}).get("tiles")
    if tiles is None or "tiled" not in str(meta.get("storage", "")).lower():
        return None
    words, levels = tiling(tiles, meta["data_window"])
    return f"tiled ({words}): written as scanlines" + (
        f", the full-resolution level only (the {levels - 1} smaller levels are not written)" if levels > 1 else "")


def warn_scanlines(path, meta: dict) -> None:
    """Say in one note that ``meta``'s tiled or mip-mapped EXR part is written as scanlines (nothing for a
    scanline part)."""
    note = storage_note(meta)
    if note is None:
        return
    import warnings

    warning = ScanlineWarning(f"{path}: {note}")
    warning.command_line = note
    warnings.warn(warning, stacklevel=3)
