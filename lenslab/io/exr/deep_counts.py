"""The sample counts of a deep EXR, from its own bytes, before OpenEXR allocates a sample.

A deep scanline chunk is ``[part number]`` (multi-part files), the chunk's first line ``y``, the packed size
of its pixel offset table, the packed and unpacked sizes of its sample data (int32, then three uint64), the
pixel offset table (for each line, one int32 per pixel: the samples of that pixel and all to its left), then
the sample data (OpenEXR, "The OpenEXR File Layout": deep scan line layout). A deep tile's chunk has the
tile's x, y and levels (four int32) in place of ``y``, and a table of the tile's lines. The tables are compressed as
the part says: none, RLE or ZIP (a zlib stream of the bytes split into even and odd halves, each byte stored
as its difference to the one before plus 128); a table as long packed as unpacked is stored raw.

:func:`deep_counts` reads every chunk's table (decompressed to at most its declared size) and gives each
deep part's total samples, largest count in one pixel and pixels with samples; :func:`check_deep` holds the
total against the input budget (:mod:`lenslab.io.budget`): what OpenEXR's Python bindings and the flattening
allocate for it, against the file's bytes, with the same limits as a flat image's decoded size.
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass

import numpy as np

from lenslab.errors import FormatError
from lenslab.inputs.limits import check_size
from lenslab.io.exr.select import part_label

#: compressions whose offset tables lenslab decodes (codes of the ``compression`` attribute): the ones the
#: OpenEXR file layout allows for deep data, with their scanlines per chunk
DEEP_LINES = {0: 1, 1: 1, 2: 1, 3: 16}
_NAMES = {0: "none", 1: "rle", 2: "zips", 3: "zip"}  # (the names lenslab's EXR writer takes)
#: bytes the bindings hold per pixel and per array they make for a pixel with samples (a NumPy array
#: object), and per sample the flattening's working arrays hold per channel (float64, a few at once).
#: Measured against ``lenslab info``'s peak resident memory beyond its start (about 80 MB): 2.1 million
#: samples in 466 195 of 1024 x 512 pixels, RGBA half + Z, estimated 810 MB, peak 700 MB; OpenEXR's stereo
#: Trunks.exr (both parts decoded) 402 MB, peak 240 MB
POINTER_BYTES, ARRAY_BYTES, WORK_BYTES = 8, 112, 48
#: bytes a stored sample takes, by pixel type
TYPE_BYTES = {"HALF": 2, "FLOAT": 4, "UINT": 4}


@dataclass(frozen=True)
class DeepCounts:
    """One deep part's samples: ``total``, ``max_per_pixel``, ``pixels`` with at least one sample."""

    total: int
    max_per_pixel: int
    pixels: int


def _unpack_rle(data: bytes, size: int) -> bytes:
    out = bytearray()
    i = 0
    while i < len(data) and len(out) <= size:
        n = struct.unpack_from("b", data, i)[0]
        if n < 0:
            out += data[i + 1:i + 1 - n]
            i += 1 - n
        else:
            out += data[i + 1:i + 2] * (n + 1)
            i += 2
    return bytes(out)


def _table(path, packed: bytes, size: int, compression: int) -> np.ndarray:
    """The unpacked offset table (``size`` bytes) as little-endian int32. (An uncompressed deep tile at the
    image's edge may hold a whole tile's table, as OpenEXR writes it: its first ``size`` bytes count.)"""
    if compression == 0 or len(packed) == size:
        raw = packed[:size]
    else:
        if compression == 1:
            raw = _unpack_rle(packed, size)
        else:
            try:
                d = zlib.decompressobj()
                raw = d.decompress(packed, size + 1)
            except zlib.error:
                raw = b""
        if len(raw) == size and size:
            t = np.cumsum(np.frombuffer(raw, np.uint8).astype(np.int64) - np.r_[0, np.full(size - 1, 128)])
            t = (t & 0xFF).astype(np.uint8)
            half = (size + 1) // 2
            out = np.empty(size, np.uint8)
            out[0::2], out[1::2] = t[:half], t[half:]
            raw = out.tobytes()
    if len(raw) != size:
        raise FormatError(f"{path}: a deep sample count table does not unpack to its {size} bytes; the file is "
                          "damaged")
    return np.frombuffer(raw, "<i4")


def _compression(code: int) -> str:
    try:
        import OpenEXR

        name = OpenEXR.Compression(code).name
    except (ImportError, ValueError, AttributeError, TypeError):  # (a code the bindings do not know)
        name = ""
    return name.replace("_COMPRESSION", "").lower() if name.endswith("_COMPRESSION") else f"code {code}"


def _chunk_boxes(path, name: str, part: dict) -> tuple[list[tuple], str]:
    """Each chunk slot's expected key (its first line, or its tile's x, y and level 0, 0) and the width and
    height of its table, in the offset table's order (by y, then x), and the leader's layout after the part
    number."""
    x0, y0, x1, y1 = part["dataWindow"]
    w, h = x1 - x0 + 1, y1 - y0 + 1
    if not part.get("deep_tiled"):
        lines = DEEP_LINES[part.get("compression", 0)]
        return [((y0 + y,), w, min(lines, h - y)) for y in range(0, h, lines)], "<iQQQ"
    tx, ty, mode = part.get("tiles") or (0, 0, 0)
    if tx <= 0 or ty <= 0 or mode & 0x0F:
        raise FormatError(f"{path}: {name} is a deep tiled image " + (
            "with mip-map levels; lenslab reads deep tiles of one level only" if tx > 0 and ty > 0 else
            "whose tile size is not positive; the file is damaged"))
    check_size(path, -(-w // tx), -(-h // ty))
    return [((i, j, 0, 0), min(tx, w - i * tx), min(ty, h - j * ty)) for j in range(-(-h // ty))
            for i in range(-(-w // tx))], "<iiiiQQQ"


def deep_counts(path, layout) -> dict[int, DeepCounts]:
    """Every deep part's :class:`DeepCounts` (by part index) from its chunks' offset tables; a deep part
    lenslab cannot count (tiled, or a compression outside ``DEEP_LINES``), a chunk outside the file or a
    table that does not add up are a :class:`FormatError` of one line."""
    parts, size, multi = layout.parts, layout.size, layout.multipart
    out: dict[int, DeepCounts] = {}
    if not any(p.get("deep") for p in parts):
        return out
    with open(path, "rb") as f:
        table_at = layout.header_end
        tables = []
        for i, part in enumerate(parts):
            x0, y0, x1, y1 = part["dataWindow"]
            comp = part.get("compression", 0)
            lines = DEEP_LINES.get(comp, 1)
            chunks = part.get("chunkCount") if multi else None
            if part.get("deep") and part.get("compression", -1) in DEEP_LINES:
                name = part_label(i, part.get("name"))
                expected = len(_chunk_boxes(path, name, part)[0])
            elif part.get("tiled") and "tiles" in part:  # (a flat tiled part's table, of one level at least)
                expected = -(-(x1 - x0 + 1) // max(part["tiles"][0], 1)) * -(-(y1 - y0 + 1) // max(part["tiles"][1], 1))
            else:
                expected = -(-(y1 - y0 + 1) // lines)
            chunks = expected if chunks is None or not part.get("deep") else max(chunks, 0)
            if part.get("deep") and chunks != expected:
                raise FormatError(f"{path}: part {i} declares {chunks} chunks where its data window needs "
                                  f"{expected}; the file is damaged")
            tables.append((table_at, chunks))
            table_at += 8 * max(chunks, 0)
        if table_at > size:
            raise FormatError(f"{path}: the chunk tables end at byte {table_at} but the file has {size} bytes; the "
                              "file is truncated")
        for i, part in enumerate(parts):
            if not part.get("deep"):
                continue
            name = part_label(i, part.get("name"))
            comp = part.get("compression", -1)
            if comp not in DEEP_LINES:
                raise FormatError(f"{path}: {name} is a deep image compressed as {_compression(comp)}; lenslab counts "
                                  f"deep samples compressed as {', '.join(_NAMES.values())} only, before reading them: "
                                  "rewrite it with one of those")
            boxes, layout_of = _chunk_boxes(path, name, part)
            per_sample = sum(TYPE_BYTES.get(t, 4) for t in part.get("channel_types", {}).values())
            at, chunks = tables[i]
            f.seek(at)
            offsets = np.frombuffer(f.read(8 * chunks), "<u8")
            total = peak = pixels = 0
            keys = len(layout_of) - 4  # the chunk's line, or its tile's x, y and levels
            for (key, w, n), off in zip(boxes, offsets.tolist()):
                where = f"line {key[0]}" if keys == 1 else f"tile {key[0]}, {key[1]}"
                leader = (4 if multi else 0) + struct.calcsize(layout_of)
                if off + leader > size:
                    raise FormatError(f"{path}: a chunk of part {i} starts at byte {off}, past the end of the file "
                                      f"({size} bytes); the file is truncated or damaged")
                f.seek(off)
                head = f.read(leader)
                if multi and struct.unpack_from("<i", head)[0] != i:
                    raise FormatError(f"{path}: a chunk of part {i} is marked as part "
                                      f"{struct.unpack_from('<i', head)[0]}; the file is damaged")
                *found, packed_table, packed_data, unpacked = struct.unpack_from(layout_of, head, 4 if multi else 0)
                if tuple(found) != key or off + leader + packed_table + packed_data > size:  # (tables are by y, x)
                    raise FormatError(f"{path}: the deep chunk of part {i} for {where} is another chunk, or runs "
                                      f"past the end of the file ({size} bytes); the file is damaged")
                table = _table(path, f.read(packed_table), 4 * w * n, comp).reshape(n, w).astype(np.int64)
                counts = np.diff(table, axis=1, prepend=0)  # (each row of a table counts from 0)
                if (counts < 0).any():
                    raise FormatError(f"{path}: a deep sample count table of part {i} ({where}) decreases; the file "
                                      "is damaged")
                in_chunk = int(table[:, -1].sum())
                if unpacked != in_chunk * per_sample:
                    raise FormatError(f"{path}: a deep chunk of part {i} ({where}) declares {unpacked} bytes of "
                                      f"samples but its table counts {in_chunk} samples of {per_sample} bytes; the "
                                      "file is damaged")
                total += in_chunk
                peak = max(peak, int(counts.max(initial=0)))
                pixels += int(np.count_nonzero(counts))
            out[i] = DeepCounts(total, peak, pixels)
    return out


def deep_bytes(part: dict, counts: DeepCounts) -> int:
    """What reading and flattening a deep part holds at once: the bindings' arrays (a pointer per pixel and
    channel group, an array object per pixel with samples, the samples at their stored type) and the
    flattening's float64 working arrays."""
    x0, y0, x1, y1 = part["dataWindow"]
    chans = max(1, len(part.get("channel_types", {})))
    per_sample = sum(TYPE_BYTES.get(t, 4) for t in part.get("channel_types", {}).values())
    return ((x1 - x0 + 1) * (y1 - y0 + 1) * chans * POINTER_BYTES + counts.pixels * chans * ARRAY_BYTES
            + counts.total * (per_sample + chans * WORK_BYTES))


def check_deep(path, layout) -> dict[int, DeepCounts]:
    """Refuse (:class:`lenslab.io.budget.BudgetError`, one line) a file whose deep samples would take more
    memory than the input budget admits for its bytes (OpenEXR decodes every part of the file at once, so
    every deep part counts); else every deep part's :class:`DeepCounts`."""
    from lenslab.io import budget

    deep = [p for p in layout.parts if p.get("deep")]
    windows = 0  # what the data windows alone take, before a table is decoded: a pointer a pixel and channel
    for part in deep:
        x0, y0, x1, y1 = part["dataWindow"]
        check_size(path, x1 - x0 + 1, y1 - y0 + 1)
        windows += deep_bytes(part, DeepCounts(0, 0, 0))
    if windows:
        _refuse(path, windows, f"its deep data windows take {budget.size_text(windows)} to read", layout.size)
    counts = deep_counts(path, layout)
    if not counts:
        return counts
    need = sum(deep_bytes(layout.parts[i], c) for i, c in counts.items())
    total = sum(c.total for c in counts.values())
    _refuse(path, need, f"its deep sample count tables hold {total} samples in "
            f"{sum(c.pixels for c in counts.values())} pixels ({budget.size_text(need)} to read and flatten)", layout.size)
    return counts


def _refuse(path, need: int, said: str, size: int) -> None:
    """The input budget (:func:`lenslab.io.budget.allowed`) on ``need`` bytes from a file of ``size``."""
    from lenslab.io import budget

    if need > budget.allowed(size):
        raise budget.BudgetError(f"{path}: {said} in a file of {budget.size_text(size)}, which may decode to at most "
                                 f"{budget.size_text(budget.allowed(size))}{budget.rule_text(size)}; refused as a "
                                 f"decompression bomb (a genuine deep image: set LENSLAB_BASE_BYTES={need})")
