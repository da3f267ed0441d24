"""Reading an EXR's pixels a band of scanlines at a time, straight into the float32 image.

OpenEXR's whole-file read (``OpenEXR.File``) gives every channel at its stored type, so a half-float
file is held twice while it becomes float32: the half pixels (2 bytes a sample) beside the float
image (4 bytes). Read a band of scanlines at a time instead, with the library converting each sample
to float as it decodes (its scanline interface, ``OpenEXR.InputFile``: ``channels(names, FLOAT,
first, last)``), the only memory of the image's size is the float32 image itself; a band is a whole
number of the file's chunks (16 scanlines for ZIP, 32 for PIZ, 256 for DWAB, a row of tiles), so no
chunk is decoded twice.

The scanline interface reads a file's first part at its full resolution, channels sampled at every
pixel; :func:`can_read` says whether a read is of that kind (others take the whole-file read). It holds
Python's lock while it decodes a band: the threads of a batch wait for each other's decoding (their
writing and other work go on between bands), while OpenEXR's own pool (``lenslab.io.exr.THREADS``)
decodes a band's chunks in parallel.
"""

from __future__ import annotations

import numpy as np

from lenslab.io.exr.chunks import LINES_PER_CHUNK

#: the NumPy type of each stored pixel type
_DTYPES = {"HALF": np.float16, "FLOAT": np.float32, "UINT": np.uint32}
#: float32 bytes of one band (a band is at least one chunk, whatever its size)
BAND_BYTES = 8 << 20


def available() -> bool:
    """Whether the installed OpenEXR bindings have the scanline interface (deprecated there, kept since
    3.3; a release without it reads whole files)."""
    try:
        import Imath  # noqa: F401  (the scanline interface's pixel types ship with the bindings)
        import OpenEXR
    except ImportError:
        return False
    return hasattr(OpenEXR, "InputFile")


def can_read(part_index: int, names: list[str], sampling: dict) -> bool:
    """Whether channels ``names`` (full names) of part ``part_index`` can be read by bands: the first
    part, each channel sampled at every pixel, and bindings with the scanline interface."""
    return part_index == 0 and all(sampling.get(n, (1, 1)) == (1, 1) for n in names) and available()


def band_rows(header: dict, width: int, channels: int) -> int:
    """Scanlines per band: a whole number of the file's chunks (scanlines per chunk of its compression,
    or its tiles' height), about :data:`BAND_BYTES` of float32. ``header``: the part's header as
    ``OpenEXR.File`` gives it."""
    tiles = header.get("tiles")
    unit = int(getattr(tiles, "ySize", 0) or 0) if tiles is not None else 0
    if unit <= 0:
        comp = int(getattr(header.get("compression"), "value", 0) or 0)
        unit = LINES_PER_CHUNK[comp] if 0 <= comp < len(LINES_PER_CHUNK) else 32
    per_row = max(1, width * max(channels, 1) * 4)
    return unit * max(1, BAND_BYTES // (per_row * unit))


def read_into(path, header: dict, names: list[str | None], types: dict[str, str], window: tuple[int, int, int, int],
              out: np.ndarray, at: tuple[int, int], threads: int, planes: dict | None = None) -> None:
    """Decode data window ``window`` (x0, y0, x1, y1) of ``path``'s first part (``header``: its header as
    ``OpenEXR.File`` gives it; the scanline interface's own header segfaults on some files) into ``out``
    (float32 H x W x C), its pixel (x0, y0) at ``out[at[1], at[0]]``, channel ``names[i]`` into
    ``out[..., i]`` (None: left as it is). The rows and columns of the window outside ``out`` are
    skipped (a data window larger than the display window). ``planes``: more channels ``{name: H x W
    array of the stored type}``, filled from the same decoding, placed as ``out`` is.

    Each channel is decoded at its stored type (``types``: name -> HALF, FLOAT or UINT) and converted by
    NumPy, as the whole-file read does: half NaN keep their payloads, which the library's own
    conversion to float does not."""
    import Imath
    import OpenEXR

    if OpenEXR.global_thread_count() != threads:
        OpenEXR.set_global_thread_count(int(threads))
    x0, y0, x1, y1 = window
    width = x1 - x0 + 1
    H, W = out.shape[:2]
    # the window's rows and columns that land inside out
    first, last = max(y0, y0 - at[1]), min(y1, y0 - at[1] + H - 1)
    left, right = max(0, -at[0]), min(width, W - at[0])
    if first > last or left >= right:
        return
    wanted = [(i, n) for i, n in enumerate(names) if n is not None] + [(n, n) for n in planes or {}]
    if not wanted:
        return
    rows = band_rows(header, width, len(wanted))
    reader = OpenEXR.InputFile(str(path))
    groups: dict[str, list[tuple[int | str, str]]] = {}  # one call per stored type (a chunk is decoded once a call)
    for i, n in wanted:
        groups.setdefault(types.get(n) if types.get(n) in _DTYPES else "FLOAT", []).append((i, n))
    start = y0 + (first - y0) // rows * rows  # bands aligned to the window's first row: whole chunks
    for a in range(start, last + 1, rows):
        b0, b1 = max(a, first), min(a + rows - 1, last)
        ys, xs = slice(b0 - y0 + at[1], b1 - y0 + at[1] + 1), slice(left + at[0], right + at[0])
        dst = out[ys, xs]
        for kind, chans in groups.items():
            decoded = reader.channels([n for _, n in chans], Imath.PixelType(getattr(Imath.PixelType, kind)), b0, b1)
            for (i, _), data in zip(chans, decoded):
                band = np.frombuffer(data, _DTYPES[kind]).reshape(b1 - b0 + 1, width)[:, left:right]
                if isinstance(i, str):
                    planes[i][ys, xs] = band
                else:
                    dst[..., i] = band


def read_image(path, header: dict, short: dict[str, str], order: list[str | None], window, display,
               data_window: bool, threads: int, types: dict[str, str],
               extra: list[str] = ()) -> tuple[np.ndarray, dict[str, str], dict[str, np.ndarray]]:
    """The first part's image as float32, channel ``order[i]`` (a short name of ``short``; None: 0) in
    channel ``i``, placed in the display window ``display`` unless ``data_window`` (0 outside the data
    window ``window``); the pixel type of each channel of ``short`` (full name -> HALF, FLOAT, UINT; ``types``:
    every channel's, from lenslab's reading of the header); and the planes of channels ``extra`` (full
    names) at their stored type, placed as the image is, decoded in the same pass."""
    x0, y0, x1, y1 = window
    X0, Y0, X1, Y1 = display
    if data_window:
        shape, at = (y1 - y0 + 1, x1 - x0 + 1), (0, 0)
    else:
        shape, at = (Y1 - Y0 + 1, X1 - X0 + 1), (x0 - X0, y0 - Y0)
    covered = data_window or tuple(window) == tuple(display)
    make = np.empty if covered and None not in order else np.zeros  # (zeros: pages mapped only when written)
    image = make((*shape, len(order)), np.float32)
    planes = {n: (np.empty if covered else np.zeros)(shape, _DTYPES.get(types.get(n), np.float32)) for n in extra}
    from lenslab.library_output import library_call

    names = [None if c is None else short[c] for c in order]
    library_call(path, lambda: read_into(path, header, names, types, window, image, at, threads, planes),
                 "OpenEXR cannot read the pixels", library_errors=(RuntimeError, OSError))
    return image, {n: types.get(n, "UNKNOWN") for n in short.values()}, planes
