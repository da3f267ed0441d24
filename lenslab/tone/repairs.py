"""Slight negative values: a lossy codec's undershoot, counted once per command instead of per file.

Tone mapping sets negative values to 0. Most negatives in real files are no error of the scene: the
lossy EXR codecs (DWAA/DWAB, B44, PXR24) and the ringing of a resampling filter leave values a little
below 0 next to black (DWAB: about -4e-4). Those are counted here, in one tally for the whole process,
and a command reports them in one line at its end (:func:`take_summary`); they are never a Python
warning. The line counts files (:mod:`lenslab.current_input`: the panels of compare-tones and the frames of a
clip are their file's, counted once), names the file when there is one, and says what the values are: down to
``SLIGHT`` a codec's or filter's undershoot, below it the resampling filter's lobes in a warp, else a lossy
codec's block undershoot. NaN, +inf and negatives beyond the rules below are real damage or real negative
light (a wrong colour space, a subtraction) and stay a :class:`~lenslab.tone.ToneWarning` per image.

What counts as slight, and why:

- any negative no lower than ``SLIGHT = 2**-10`` (9.8e-4 of white): one half-float step at 1.0, the
  precision EXR's half holds near white; once sRGB-encoded about three 8-bit code values below black,
  invisible on a display, which clips at 0 anyway;
- in an image (H x W x C), negatives no lower than ``BLOCK_SLIGHT = 2**-5`` (3 %) of the brightest value
  of their 8 x 8 block (blocks aligned to the image's corner, all channels): DWAA/DWAB quantise each
  8 x 8 block's DCT relative to the block's content, so their undershoot scales with the brightest value
  next to it. Measured on eight DWAB panoramas (city, courtyard, forest, interior, night, studio,
  sunrise, sunset): at most 1.5 % of the block's brightest value (down to -0.0039 absolute), and 0.44 %
  after a bilinear warp; 2^-5 leaves twice that margin. Negative light from a colour conversion is a
  sizeable part of the pixel's own value (BT.2020 green in Rec.709: -9 %), and filter ringing next to a
  highlight (Lanczos beside the sun: 40 % to 360 % of the block) stays above it: both are reported per
  image. (The colours of an integer file on wider primaries outside Rec.709's gamut never reach here: the
  commands clip them first and say so, :mod:`lenslab.io.colour.gamut`.)
"""

from __future__ import annotations

import contextlib
import copy
import threading
from typing import Iterator

#: negatives down to -SLIGHT are a codec's or filter's undershoot (see the module docstring)
SLIGHT = 2.0 ** -10
#: in an image: negatives down to -BLOCK_SLIGHT times their 8 x 8 block's brightest value
BLOCK_SLIGHT = 2.0 ** -5
BLOCK = 8


def slight(image, lowest: float) -> bool:
    """Whether every negative of ``image`` (float32; an H x W x C or H x W image, or any array of values),
    the lowest being ``lowest``, is slight by the rules of the module docstring."""
    import numpy as np

    if not lowest < 0:
        return True
    if lowest >= -SLIGHT:
        return True
    x = np.asarray(image)
    if x.ndim not in (2, 3) or not np.isfinite(lowest):
        return False
    hi = x.max(axis=-1) if x.ndim == 3 else x
    lo = x.min(axis=-1) if x.ndim == 3 else x
    h, w = hi.shape
    h8, w8 = -(-h // BLOCK) * BLOCK, -(-w // BLOCK) * BLOCK
    if (h8, w8) != (h, w):
        hi = np.pad(hi, ((0, h8 - h), (0, w8 - w)))
        lo = np.pad(lo, ((0, h8 - h), (0, w8 - w)))
    with np.errstate(invalid="ignore"):  # NaN never reaches here: the caller counted none
        bmax = hi.reshape(h8 // BLOCK, BLOCK, w8 // BLOCK, BLOCK).max(axis=(1, 3))
        bmin = lo.reshape(h8 // BLOCK, BLOCK, w8 // BLOCK, BLOCK).min(axis=(1, 3))
    return bool((bmin >= -np.maximum(BLOCK_SLIGHT * bmax, SLIGHT)).all())

_lock = threading.Lock()


def _empty() -> dict:
    # files: the inputs the images came from (lenslab.inputs), in order; images: images from no named input
    return {"values": 0, "images": 0, "lowest": 0.0, "files": {}, "lobes": False}


_tally = _empty()


def add(count: int, lowest: float) -> None:
    """Count ``count`` slight negatives (the lowest ``lowest``) repaired in one image: under the input file
    the command is working on (:mod:`lenslab.current_input`; the images of one file, compare-tones' panels or a clip's
    frames, count as that file once), else as an image of its own."""
    from lenslab.current_input import CURRENT, RESAMPLED

    source = CURRENT.get()
    with _lock:
        _merge(int(count), 0 if source else 1, float(lowest), [source] if source else [],
               RESAMPLED.get() and lowest < -SLIGHT)


def _merge(values: int, images: int, lowest: float, files, lobes: bool) -> None:
    _tally["values"] += values
    _tally["images"] += images
    _tally["lowest"] = min(_tally["lowest"], lowest)
    _tally["files"].update(dict.fromkeys(files))
    _tally["lobes"] = _tally["lobes"] or bool(lobes)


def _take() -> dict:
    global _tally
    with _lock:
        out, _tally = _tally, _empty()
    return out


@contextlib.contextmanager
def uncounted() -> Iterator[None]:
    """Within the block, repairs are not added to the tally: the same values of the same file repaired again
    (compare-tones' second and third panel of one image)."""
    global _tally
    with _lock:
        saved = copy.deepcopy(_tally)
    try:
        yield
    finally:
        with _lock:
            _tally = saved


def take() -> tuple[int, int, float]:
    """``(values, images, lowest)`` counted since the last call (images: the files, each once, and the images
    from no named file), and the tally reset."""
    t = _take()
    return t["values"], t["images"] + len(t["files"]), t["lowest"]


def take_summary() -> str | None:
    """One line for a command's end, or None when nothing was repaired (the tally is reset). It names the file
    when there is one, counts files (not the images made from them) when there are several, and calls the
    values what they are: down to -SLIGHT a codec's or filter's undershoot; below it, in a resampled image, the
    resampling filter's negative lobes, else a lossy codec's block undershoot."""
    t = _take()
    values, lowest = t["values"], t["lowest"]
    if not values:
        return None
    files, images = list(t["files"]), t["images"]
    where = []
    if len(files) == 1 and not images:
        where.append(files[0])
    elif files:
        where.append(f"{len(files)} files")
    if images:
        where.append(f"{images} image{'s' if images != 1 else ''}")
    s = "s" if values != 1 else ""
    if lowest >= -SLIGHT:
        what = f"{values} slightly negative value{s} (down to {lowest:.2g}, a lossy codec's or filter's undershoot)"
    elif t["lobes"]:
        what = f"{values} negative value{s} from the resampling filter's lobes (down to {lowest:.2g})"
    else:
        what = (f"{values} negative value{s} of a lossy codec's 8 x 8 blocks (down to {lowest:.2g}, within "
                f"{BLOCK_SLIGHT:.1%} of their block's brightest value)")
    return f"{what} set to 0 in {' and '.join(where)}"


#: how a cluster task hands its tally to the command that reports it (a note the command parses back)
_NOTE = "slight negatives repaired:"


def take_note() -> str | None:
    """This process's tally as a note for another process (a cluster worker's task), and the tally reset."""
    import json

    t = _take()
    return f"{_NOTE}{json.dumps([t['values'], t['images'], t['lowest'], list(t['files']), t['lobes']])}" \
        if t["values"] else None


def absorb_note(note: str, names: dict | None = None) -> bool:
    """Add a worker's :func:`take_note` to this process's tally, its files named through ``names`` (a worker's absolute
    path -> the path as the command was given it: a task may hand back the tally of another task of its worker);
    False for any other note."""
    import json

    if not note.startswith(_NOTE):
        return False
    values, images, lowest, files, lobes = json.loads(note[len(_NOTE):])
    files = [(names or {}).get(f, f) for f in files]
    with _lock:
        _merge(int(values), int(images), float(lowest), files, lobes)
    return True
