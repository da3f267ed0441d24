"""The layout of a TIFF read before tifffile sees it: the page chain (loops and runaway chains refused)
and the first page's size, samples and strip or tile tables against the bytes the file holds, read by
:mod:`lenslab.io.tiff.walk` (classic TIFF and BigTIFF, both byte orders).
"""

from __future__ import annotations

import os

import numpy as np

from lenslab.errors import FormatError
from lenslab.io.tiff.walk import CODES, Loop, Outside, chain, file_read, header, value_bytes

#: pages followed before a chain is called runaway
MAX_PAGES = 1 << 16
#: the best compression ratio each TIFF compression scheme can reach (raw bytes per stored byte), so
#: that a strip table holding fewer bytes cannot be real: none 1; PackBits 128 bytes from 2; LZW with
#: 12-bit codes about 1365; Deflate 1032; JPEG about 512 (one bit per 8 x 8 block); others (zstd, LZMA,
#: WebP, JPEG XL...) 32768, zstd's one-byte run blocks
MAX_RATIO = {1: 1, 32773: 64, 5: 1400, 8: 1100, 32946: 1100, 7: 1024, 6: 1024}
_OTHER_RATIO = 32768
#: the types whose values are read (checked against the file's bytes): all but the rationals
_NUMBERS = {kind: code for kind, code in CODES.items() if kind not in (5, 10)}
_TAGS = {256, 257, 258, 259, 273, 277, 278, 279, 284, 322, 323, 324, 325, 32997}


def layout(path) -> dict:
    """``{"pages", "tags"}``: the number of pages and the first page's tags of interest (arrays)."""
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        read, head = file_read(f), f.read(16)
        found = header(head)
        if found is None:
            raise FormatError(f"{path}: not a TIFF (its first bytes are {head[:4]!r})")
        if found.first is None:
            raise FormatError(f"{path}: the BigTIFF header is cut short")
        pages, tags, what = 0, {}, ""
        try:
            for ifd in chain(read, size, found, MAX_PAGES):
                pages += 1
                for tag, kind, count, field in ifd if pages == 1 else ():
                    if kind in _NUMBERS:
                        what = f"values of tag {tag}"
                        raw = value_bytes(read, size, found.order, kind, count, field)
                        if tag in _TAGS:
                            tags[tag] = np.frombuffer(raw, np.dtype(_NUMBERS[kind]).newbyteorder(found.order))
        except Outside as exc:
            part, at, _ = exc.args
            what = {"count": "page directory", "entries": f"directory of page {pages + 1}"}.get(part, what)
            raise FormatError(f"{path}: the {what} at byte {at} runs past the end of the file ({size} bytes); "
                              "the file is truncated or damaged") from None
        except Loop as exc:
            page, back_to = exc.args
            raise FormatError(f"{path}: the page chain loops (page {page} points back to page {back_to}); the file is "
                              "damaged or hostile" if back_to else f"{path}: the page chain runs past {MAX_PAGES} pages; "
                              "the file is damaged") from None
    if not pages:
        raise FormatError(f"{path}: the TIFF holds no image")
    return {"pages": pages, "tags": tags, "size": size}


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
