"""The layout of a TIFF read before tifffile sees it: the page chain (loops and runaway chains refused)
and the first page's size, samples and strip or tile tables against the bytes the file holds.

Classic TIFF (``II*\\0``/``MM\\0*``: 2-byte entry counts, 12-byte entries, 4-byte offsets) and BigTIFF
(``+``: 8-byte counts, 20-byte entries, 8-byte offsets), as the TIFF 6.0 specification and the BigTIFF
design note lay them out.
"""

from __future__ import annotations

import os
import struct

import numpy as np

from lenslab.errors import FormatError

#: pages followed before a chain is called runaway
MAX_PAGES = 1 << 16
#: the best compression ratio each TIFF compression scheme can reach (raw bytes per stored byte), so
#: that a strip table holding fewer bytes cannot be real: none 1; PackBits 128 bytes from 2; LZW with
#: 12-bit codes about 1365; Deflate 1032; JPEG about 512 (one bit per 8 x 8 block); others (zstd, LZMA,
#: WebP, JPEG XL...) 32768, zstd's one-byte run blocks
MAX_RATIO = {1: 1, 32773: 64, 5: 1400, 8: 1100, 32946: 1100, 7: 1024, 6: 1024}
_OTHER_RATIO = 32768
_TYPES = {1: "B", 2: "B", 3: "H", 4: "I", 6: "b", 7: "B", 8: "h", 9: "i", 11: "f", 12: "d", 16: "Q", 17: "q",
          18: "Q", 13: "I"}
_TAGS = {256, 257, 258, 259, 273, 277, 278, 279, 284, 322, 323, 324, 325, 32997}


def _read_at(f, size, offset, n, what):
    if offset < 0 or n < 0 or offset + n > size:
        raise FormatError(f"{f.name}: the {what} at byte {offset} runs past the end of the file ({size} bytes); "
                          "the file is truncated or damaged")
    f.seek(offset)
    return f.read(n)


def _values(f, size, bo, big, entry):
    tag, typ = struct.unpack(bo + "HH", entry[:4])
    count = struct.unpack(bo + ("Q" if big else "I"), entry[4:12 if big else 8])[0]
    code = _TYPES.get(typ)
    if code is None:
        return tag, None
    nbytes = count * struct.calcsize(code)
    inline = 8 if big else 4
    if nbytes <= inline:
        raw = entry[(12 if big else 8):(12 if big else 8) + nbytes]
    else:
        off = struct.unpack(bo + ("Q" if big else "I"), entry[12:20] if big else entry[8:12])[0]
        raw = _read_at(f, size, off, nbytes, f"values of tag {tag}")
    return tag, np.frombuffer(raw, np.dtype(code).newbyteorder("<" if bo == "<" else ">"))


def layout(path) -> dict:
    """``{"pages", "tags"}``: the number of pages and the first page's tags of interest (arrays)."""
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        head = f.read(16)
        if len(head) < 8 or head[:2] not in (b"II", b"MM"):
            raise FormatError(f"{path}: not a TIFF (its first bytes are {head[:4]!r})")
        bo = "<" if head[:2] == b"II" else ">"
        version = struct.unpack(bo + "H", head[2:4])[0]
        big = version == 43
        if big:
            if len(head) < 16:
                raise FormatError(f"{path}: the BigTIFF header is cut short")
            offset = struct.unpack(bo + "Q", head[8:16])[0]
        else:
            offset = struct.unpack(bo + "I", head[4:8])[0]
        count_fmt, count_n, entry_n, off_fmt, off_n = (("Q", 8, 20, "Q", 8) if big else ("H", 2, 12, "I", 4))
        seen: dict[int, int] = {}
        tags: dict[int, np.ndarray] = {}
        while offset:
            if offset in seen:
                raise FormatError(f"{path}: the page chain loops (page {len(seen) + 1} points back to page "
                                  f"{seen[offset] + 1}); the file is damaged or hostile")
            if len(seen) >= MAX_PAGES:
                raise FormatError(f"{path}: the page chain runs past {MAX_PAGES} pages; the file is damaged")
            seen[offset] = len(seen)
            n = struct.unpack(bo + count_fmt, _read_at(f, size, offset, count_n, "page directory"))[0]
            table = _read_at(f, size, offset + count_n, n * entry_n + off_n, f"directory of page {len(seen)}")
            if len(seen) == 1:
                for i in range(n):
                    tag, vals = _values(f, size, bo, big, table[i * entry_n:(i + 1) * entry_n])
                    if tag in _TAGS and vals is not None:
                        tags[tag] = vals
            offset = struct.unpack(bo + off_fmt, table[n * entry_n:])[0]
    if not seen:
        raise FormatError(f"{path}: the TIFF holds no image")
    return {"pages": len(seen), "tags": tags, "size": size}


def _one(tags, tag, default=None):
    v = tags.get(tag)
    return default if v is None or v.size == 0 else int(v[0])


def declare_tiff(path, **_):
    """:class:`lenslab.io.budget.Declared` of a TIFF's first page, its strip or tile table checked."""
    from lenslab.io.budget import Declared

    found = layout(path)
    tags, size = found["tags"], found["size"]
    w, h = _one(tags, 256, 0), _one(tags, 257, 0)
    depth = _one(tags, 32997, 1)
    spp = _one(tags, 277, 1)
    bps = tags.get(258)
    bits = int(bps.max()) if bps is not None and bps.size else 1
    if not (0 < spp <= 64 and 0 < bits <= 64 and 0 < depth <= 1 << 16):
        raise FormatError(f"{path}: the TIFF declares {spp} samples of {bits} bits (depth {depth}); the file is "
                          "damaged")
    tiled = 324 in tags or 322 in tags
    offsets = tags.get(324 if tiled else 273)
    counts = tags.get(325 if tiled else 279)
    if offsets is None or counts is None or offsets.size != counts.size or offsets.size == 0:
        raise FormatError(f"{path}: the TIFF's {'tile' if tiled else 'strip'} table is missing or inconsistent")
    planes = spp if _one(tags, 284, 1) == 2 else 1
    if tiled:
        tw, tl = _one(tags, 322, 0), _one(tags, 323, 0)
        if tw <= 0 or tl <= 0:
            raise FormatError(f"{path}: the TIFF's tile size {tw} x {tl} is invalid")
        need_chunks = -(-w // tw) * -(-h // tl) * planes * depth
    else:
        rps = min(_one(tags, 278, h) or h, max(h, 1))
        need_chunks = -(-h // max(rps, 1)) * planes * depth
    if offsets.size < need_chunks:
        raise FormatError(f"{path}: the TIFF declares {w} x {h} pixels in {need_chunks} "
                          f"{'tiles' if tiled else 'strips'} but its table lists {offsets.size}; it is damaged")
    ends = offsets.astype(np.uint64) + counts.astype(np.uint64)
    if ends.size and (int(ends.max()) > size or int(counts.min()) == 0):
        bad = int(np.argmax((ends > size) | (counts == 0)))
        raise FormatError(f"{path}: {'tile' if tiled else 'strip'} {bad + 1} of {offsets.size} "
                          f"{'is empty' if counts[bad] == 0 else 'runs past the end of the file'}; the file is "
                          "truncated or damaged")
    raw = w * h * depth * spp * bits // 8
    ratio = MAX_RATIO.get(_one(tags, 259, 1), _OTHER_RATIO)
    return Declared(w, h * depth, min(spp, 4), min_bytes=-(-raw // ratio), held=int(counts.astype(np.uint64).sum()),
                    what=f"{'tile' if tiled else 'strip'} data")
