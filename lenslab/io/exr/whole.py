"""Reading an EXR through OpenEXR's whole-file interface (``OpenEXR.File``): any part, channels
subsampled or luminance-chroma. The first part's full-resolution channels read by bands instead
(:mod:`lenslab.io.exr.bands`), with no copy of the image at its stored type beside the float32 one."""

from __future__ import annotations

import numpy as np

from lenslab.errors import FormatError, clip
from lenslab.io.exr.colour import luminance_weights, upsample, yca_to_rgb


def _to_float(pixels: np.ndarray) -> np.ndarray:
    return pixels if pixels.dtype == np.float32 else pixels.astype(np.float32)


def read_whole(path, index: int, header: dict, names: list[str], short: dict[str, str], order: list[str | None],
               converted: bool, sampling: dict, window: tuple[int, int, int, int],
               threads: int) -> tuple[np.ndarray, dict[str, str], dict]:
    """The data window of part ``index`` as float32, channel ``order[i]`` (a short name of ``short``;
    None: 0) in channel ``i``; ``converted``: ``order`` starts with Y, RY, BY, which become R, G, B.
    Also the pixel type of each channel read from (full name -> HALF, FLOAT, UINT), and the part's
    channels as the library decoded them (the other channels' planes come from this one decoding)."""
    import OpenEXR

    from lenslab.io.exr import plain_value

    x0, y0, x1, y1 = window
    w, h = x1 - x0 + 1, y1 - y0 + 1
    # plain RGB(A) of one sample type: the library interleaves while decoding (no copy afterwards)
    whole = "RGBA" if sorted(names) == ["A", "B", "G", "R"] else "RGB" if sorted(names) == ["B", "G", "R"] else None
    try:
        types = {plain_value(c.type()) for c in header.get("channels", [])}
    except (IndexError, ValueError, RuntimeError, TypeError):  # some headers do not say until the pixels are read
        types = set()
    if whole and (len(types) != 1 or set(sampling.values()) != {(1, 1)}):
        whole = None
    chans = part_channels(path, index, threads, separate=whole is None)
    if whole is not None:
        block = chans.get(whole)
        if block is None or block.pixels is None or block.pixels.shape != (h, w, len(whole)):
            raise FormatError(f"{path}: the pixel data does not match the header; the file is damaged")
        return (np.ascontiguousarray(block.pixels, dtype=np.float32), {n: next(iter(types)) for n in short.values()},
                chans)

    def get(name: str) -> np.ndarray:
        ch = chans.get(short[name])
        if ch is None or ch.pixels is None:
            raise FormatError(f"{path}: channel {clip(short[name])} has no pixel data; the file is damaged")
        pix = ch.pixels
        if pix.dtype == object:
            raise FormatError(f"{path}: channel {clip(short[name])} holds deep samples; lenslab reads flat images")
        xs, ys = sampling.get(short[name], (1, 1))
        if (xs, ys) != (1, 1):
            return upsample(pix, xs, ys, w, h, x0, y0)
        if pix.shape != (h, w):
            raise FormatError(f"{path}: channel {clip(short[name])} is {pix.shape[1]} x {pix.shape[0]}, not the data "
                              f"window's {w} x {h}; the file is damaged")
        return pix  # half, float or uint: converted to float32 once, when copied into the image

    if converted:
        rgb = yca_to_rgb(_to_float(get("Y")), get("RY"), get("BY"), luminance_weights(header.get("chromaticities")))
        planes = [rgb[..., 0], rgb[..., 1], rgb[..., 2]] + [get(c) for c in order[3:]]
    else:
        planes = [None if c is None else get(c) for c in order]
    image = np.empty((h, w, len(planes)), np.float32)
    for i, plane in enumerate(planes):  # one pass per channel: conversion and interleaving together
        image[..., i] = 0 if plane is None else plane
    return image, {n: plain_value(c.type()) for n, c in chans.items() if n in short.values()}, chans


def part_channels(path, index: int, threads: int, separate: bool = True):
    """The channels of part ``index`` as OpenEXR's whole-file read gives them (``separate``: one array a
    channel); what the library prints of a damaged file is kept off the terminal, its first line the cause."""
    import OpenEXR

    from lenslab.library_output import library_call

    return library_call(path, lambda: OpenEXR.File(str(path), separate_channels=separate,
                                                   num_threads=threads).parts[index].channels,
                        "OpenEXR cannot read the pixels", library_errors=(RuntimeError, OSError))


def placed(image: np.ndarray, window, display) -> np.ndarray:
    """The data window's ``image`` (H x W or H x W x C, its dtype kept) placed in the display window (0
    outside it)."""
    x0, y0, x1, y1 = window
    X0, Y0, X1, Y1 = display
    out = np.zeros((Y1 - Y0 + 1, X1 - X0 + 1) + image.shape[2:], image.dtype)
    ix0, iy0, ix1, iy1 = max(x0, X0), max(y0, Y0), min(x1, X1), min(y1, Y1)
    if ix0 <= ix1 and iy0 <= iy1:
        out[iy0 - Y0:iy1 - Y0 + 1, ix0 - X0:ix1 - X0 + 1] = image[iy0 - y0:iy1 - y0 + 1, ix0 - x0:ix1 - x0 + 1]
    return out


class DataOutsideDisplayWarning(UserWarning):
    """An EXR whose data window lies wholly outside its display window, read as the display window (as a compositor
    shows it): the image holds none of the stored pixels. ``command_line``: the note without the path."""


def note_data_outside(path, window, display) -> None:
    """Say that the display window of ``path`` shows none of its data window (both ``(x0, y0, x1, y1)``), if so."""
    x0, y0, x1, y1 = window
    X0, Y0, X1, Y1 = display
    if x1 >= X0 and x0 <= X1 and y1 >= Y0 and y0 <= Y1:
        return
    import warnings

    note = (f"the data window {list(window)} lies wholly outside the display window {list(display)}: the image (its "
            "display window) holds none of the stored pixels, only 0; 'lenslab convert --data-window' writes them")
    warning = DataOutsideDisplayWarning(f"{path}: {note}")
    warning.command_line = note
    warnings.warn(warning, stacklevel=3)
