"""One input budget for every format: what a file's header declares against what its bytes can hold.

Each format plugin (:class:`lenslab.io.plugin.Format`) has a ``declare`` hook that reads only the
header and the file's tables (TIFF strip and tile byte counts, JPEG scan data, PNG ``IDAT`` chunks,
EXR windows and chunk tables, Radiance scanline minimums, raw sample counts) and returns a
:class:`Declared`: the size of the image a read would allocate, and the fewest bytes that a file
declaring it must hold (each format's best possible compression). :func:`admit` then refuses, with
one line naming the file and before any pixel memory exists:

- a size beyond :data:`lenslab.inputs.limits.MAX_PIXELS` (the same cap as ``--size``);
- fewer bytes than the declared image needs (a 302-byte TIFF declaring 20000 x 20000 floats);
- a decoded float image larger than :func:`allowed` of the file's bytes ``b``:
  ``max(BASE_BYTES, SMALL_RATIO * min(b, SMALL_FILE) + MAX_RATIO * max(b - SMALL_FILE, 0))``, i.e. any
  file may decode to :data:`BASE_BYTES` (96 MiB: a 4096 x 2048 RGB panorama in float32), each of its first
  :data:`SMALL_FILE` (1 MiB) bytes to :data:`SMALL_RATIO` (512) bytes of float32, each byte beyond to
  :data:`MAX_RATIO` (4096). The rule is continuous and increasing in ``b`` (one more byte buys at most
  4096 bytes), so no file size admits gigabytes more than one byte less. The refusal names the
  ``LENSLAB_BASE_BYTES`` value that admits the file; ``LENSLAB_SMALL_RATIO`` and ``LENSLAB_MAX_RATIO``
  change the two ratios (``LENSLAB_SMALL_RATIO=1``: 96 MiB for every file under 1 MiB, as a machine that
  must hold each command within 200 MB of its start needs).

:data:`SMALL_RATIO` is measured (``tools/budget_ratios.py``: decoded float bytes per file byte, as the
``declare`` hooks see them). Genuine images: 70-degree views of the eight real 1024 x 512 panoramas
(``lenslab warp``, exposure auto, 3 yaws each), saved by Pillow as JPEG at qualities 70 to 95 (4:2:0), PNG
and HEIC (pillow-heif's default quality). A 70-degree view spans 199 of a panorama's pixels, so the ratio
grows with the view's size, which softens it: at 256 x 192 (the panorama's own detail, as in a sharp
photo) JPEG reaches at most 211 (q70; 117 at q90), HEIC 358, PNG 17; at 512 x 384 JPEG 301, HEIC 564; at
1024 x 768 (5 times softer) JPEG 420 (q70; 233 at q90), HEIC 902; at 4000 x 3000 (20 times: softer than
any photo) JPEG 608 (q70; 404 at q90, 254 at q95), HEIC 1579. Phone photos that the 96 MiB rule refused:
a 12 MP JPEG of 0.85 MB is 172, a 12 MP HEIC of 0.79 MB 185. The real files of ../shared/data/formats: at
most 330 (an EXR). Flat colour, the most a format's files reach (12 MP, each at its smallest settings):
JPEG baseline 4:2:0 (OpenCV, Pillow) 766, optimized or progressive 2031 to 2040, PNG 3032 to 3437, TIFF
Deflate 3579 (LZW 642), EXR ZIP 1772, PXR24 1434, PIZ 576, DWAA 6804, HEIC 18488 to 18646. Below 512
whatever their content: Radiance run lengths 186 (at most 190 by the format's rules), EXR RLE 121, a
baseline 4:4:4 JPEG 438. So 512 admits every view at the panoramas' own detail (by 1.43 times the
highest, a HEIC), every JPEG view up to 5 times softer, and the phone photos above by 2.8 times; it
refuses the flat baseline JPEG by 1.5 times, progressive JPEG by 4, EXR ZIP by 3.5 (PIZ by 1.1), PNG and TIFF
Deflate by 5.9 and more, HEIC by 36. It refuses HEIC views softer than the panoramas' detail (2 of 24 at
512 x 384, 13 of 24 at 1024 x 768, all at 4000 x 3000) and the lowest-quality JPEGs of the 4000 x 3000 views
(2 of 8 at q70, 1 at q80): smooth, dark or plain pictures whose ratio no flat file's beats by much.

What it costs (``lenslab bench memory``, peak resident memory beyond a command's start): an image within
:data:`BASE_BYTES`, from any file, within 200 MB (190 MB measured, a warp: ``memory.edge_*``); a larger
one, from a file of ``b`` bytes under 1 MiB, up to 512 ``b`` of float32 (268 MB for 0.5 MiB, 537 MB for
1 MiB), which each command holds 1.07 to 1.39 times over (``memory.edge_{format}_{KiB}k_*``: flat EXR,
JPEG and HEIC files padded to the edge): 303 to 374 MB for a file of 0.5 MiB, 576 to 710 MB for 1 MiB.
So every command passes 200 MB on a 0.5 MiB file at the edge.

A format without a ``declare`` hook gets only the pixel cap its reader applies: every plugin should
declare.
"""

from __future__ import annotations

import os
import stat
from dataclasses import dataclass, field
from pathlib import Path

from lenslab.errors import FormatError
from lenslab.inputs.limits import env_int


#: a decoded float image up to this size is admitted whatever its file's size: what every command holds
#: within 200 MB beyond its start with a margin (``lenslab bench memory``, ``memory.edge_*``)
BASE_BYTES = env_int("LENSLAB_BASE_BYTES", 96 << 20)
#: each of a file's first SMALL_FILE bytes may decode to this many bytes of float32 (measured: see above)
SMALL_RATIO = env_int("LENSLAB_SMALL_RATIO", 512)
#: each byte of a file beyond its first SMALL_FILE may decode to this many bytes of float32
MAX_RATIO = env_int("LENSLAB_MAX_RATIO", 4096)
#: where the ratio of decoded float bytes per file byte steps from SMALL_RATIO to MAX_RATIO
SMALL_FILE = 1 << 20


#: images up to this size decoded are left to their reader to find truncated (it says where)
SMALL_BYTES = 4 << 20


class BudgetError(FormatError):
    """A file declares more than its bytes can hold, or more than the budget admits."""


@dataclass(frozen=True)
class Declared:
    """What a header declares: the decoded image (``width x height x channels`` float32, ``frames``
    of them one at a time) and ``min_bytes``, the fewest bytes of ``held`` (the data the header points
    to; the whole file when None) that such an image needs, reckoned as ``what`` says."""

    width: int
    height: int
    channels: int = 3
    min_bytes: int = 0
    held: int | None = None
    what: str = "pixel data"
    #: appended to a refusal of the ratio rule (how to read less)
    hint: str = ""
    #: float bytes a read decodes beside the image (an Ultra HDR JPEG's gain map), counted with it
    extra_bytes: int = 0
    #: what the hook parsed of the header, which :func:`lenslab.io.read` gives the format's reader back
    #: (``parsed=``) so that a read parses the header once; None: nothing to give
    parsed: object = field(default=None, compare=False, repr=False)

    @property
    def float_bytes(self) -> int:
        return self.width * self.height * max(1, min(self.channels, 4)) * 4 + self.extra_bytes


def size_text(n: int) -> str:
    """A byte count as a user reads it: 146 MB, or 300 bytes below 0.1 MB."""
    return f"{n / 1e6:.3g} MB" if n >= 1e5 else f"{n} bytes"


def regular_size(path: Path) -> int:
    """The size of a regular file; FormatError for a device, FIFO or other special file."""
    st = os.stat(path)
    if not stat.S_ISREG(st.st_mode):
        raise FormatError(f"{path}: not a regular file (a device, FIFO or socket); give an image file")
    return st.st_size


def check(path, declared: Declared, file_bytes: int) -> None:
    """Refuse ``declared`` for a file of ``file_bytes`` bytes (see the module docstring)."""
    from lenslab.inputs.limits import check_size

    w, h = declared.width, declared.height
    check_size(path, w, h, declared.channels)
    held = file_bytes if declared.held is None else declared.held
    need = declared.float_bytes
    if held < declared.min_bytes and need > SMALL_BYTES:  # (a small image: the reader says where it breaks)
        raise BudgetError(f"{path}: the header declares {w} x {h} pixels, which need at least "
                          f"{size_text(declared.min_bytes)} of {declared.what}; the file holds {size_text(held)}; it is truncated, "
                          "damaged or hostile")
    if need > allowed(file_bytes):
        raise BudgetError(f"{path}: the header declares {w} x {h} pixels ({size_text(need)} decoded) from a file of "
                          f"{size_text(file_bytes)}, which may decode to at most {size_text(allowed(file_bytes))}"
                          f"{rule_text(file_bytes)}; refused as a decompression bomb{declared.hint} "
                          f"(a genuine image: set LENSLAB_BASE_BYTES={need})")


def allowed(file_bytes: int) -> int:
    """The most bytes of decoded float32 a file of ``file_bytes`` may declare: the larger of
    :data:`BASE_BYTES` and :data:`SMALL_RATIO` per byte of its first :data:`SMALL_FILE` bytes plus
    :data:`MAX_RATIO` per byte beyond them (continuous and increasing in ``file_bytes``)."""
    first = min(max(file_bytes, 0), SMALL_FILE)
    return max(BASE_BYTES, SMALL_RATIO * first + MAX_RATIO * (max(file_bytes, 0) - first))


def rule_text(file_bytes: int) -> str:
    """Which part of :func:`allowed` gives a file of ``file_bytes`` its budget, as a user reads it, in brackets
    after the budget; empty where it is the budget of any file."""
    if allowed(file_bytes) == BASE_BYTES:
        return ""
    if file_bytes <= SMALL_FILE:
        return f" ({SMALL_RATIO} times its size)"
    return f" ({SMALL_RATIO} times its first 1 MiB and {MAX_RATIO} times the rest)"


def admit(path, fmt, **options) -> Declared | None:
    """Run ``fmt``'s ``declare`` hook on ``path`` and :func:`check` the answer; None if it has none."""
    path = Path(path)
    size = regular_size(path)
    if fmt.declare is None:
        return None
    try:
        declared = fmt.declare(path, **options)
    except (EOFError, IndexError, ValueError, OverflowError) as exc:
        if isinstance(exc, FormatError):
            raise
        raise FormatError(f"{path}: the {fmt.title} header is damaged ({type(exc).__name__})") from None
    if declared is not None:
        check(path, declared, size)
    return declared


def admit_clip(path) -> Declared | None:
    """:func:`admit` a video clip (its boxes, frame rate and one decoded frame) before its frames are
    streamed."""
    from lenslab.io.registry import get

    return admit(path, get("video"))
