"""One input budget for every format: what a file's header declares against what its bytes can hold.

Each format plugin (:class:`lenslab.io.plugin.Format`) has a ``declare`` hook that reads only the
header and the file's tables (TIFF strip and tile byte counts, JPEG scan data, PNG ``IDAT`` chunks,
EXR windows and chunk tables, Radiance scanline minimums, raw sample counts) and returns a
:class:`Declared`: the size of the image a read would allocate, and the fewest bytes that a file
declaring it must hold (each format's best possible compression). :func:`admit` then refuses, with
one line naming the file and before any pixel memory exists:

- a size beyond :data:`lenslab.inputs.limits.MAX_PIXELS` (the same cap as ``--size``);
- fewer bytes than the declared image needs (a 302-byte TIFF declaring 20000 x 20000 floats);
- a decoded float image larger than :data:`BASE_BYTES` (96 MiB) from a file under :data:`SMALL_FILE`
  (1 MiB), however well it compresses. 96 MiB is exactly a 4096 x 2048 RGB panorama in float32: the
  panoramas people share on the web (a 4096 x 2048 JPEG or PNG under 1 MB) are read, and every command
  on an image at this limit peaks within 200 MB beyond its start (``lenslab bench memory``, the
  ``memory.edge_*`` figures: a flat RGBA image of the budget). A 4096 x 2048 RGBA image (128 MiB) from a
  file under 1 MB is refused: a command reads it into one float image of its size, and a warp holds
  that source, its output and its maps, which passes 200 MB. Genuine flat images beyond the limit are
  refused too (a flat 6144 x 3072 RGB float EXR, ZIP, decodes to 226 MB); ``LENSLAB_BASE_BYTES`` admits them;
- a decoded float image larger than :data:`MAX_RATIO` (4096) times the file's bytes, once it passes
  :data:`BASE_BYTES`. 4096 is above what Deflate's 1032:1 gives a flat 16-bit or half-float image,
  which lenslab's own EXR and PNG writers reach on a flat colour; ``LENSLAB_MAX_RATIO`` changes it.

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
#: beyond BASE_BYTES, the decoded float image may be at most this many times the file's bytes
MAX_RATIO = env_int("LENSLAB_MAX_RATIO", 4096)
#: a file smaller than this never decodes to more than BASE_BYTES
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
    #: what the hook parsed of the header, which :func:`lenslab.io.read` gives the format's reader back
    #: (``parsed=``) so that a read parses the header once; None: nothing to give
    parsed: object = field(default=None, compare=False, repr=False)

    @property
    def float_bytes(self) -> int:
        return self.width * self.height * max(1, min(self.channels, 4)) * 4


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
    if need > BASE_BYTES and file_bytes < SMALL_FILE:
        raise BudgetError(f"{path}: the header declares {w} x {h} pixels ({size_text(need)} decoded) from a file of "
                          f"{size_text(file_bytes)}; a file under 1 MB may decode to at most {size_text(BASE_BYTES)}; refused as "
                          f"a decompression bomb{declared.hint} (a genuine image: set LENSLAB_BASE_BYTES={need})")
    if need > BASE_BYTES and need > MAX_RATIO * file_bytes:
        raise BudgetError(f"{path}: the header declares {w} x {h} pixels ({size_text(need)} decoded) from a file of "
                          f"{size_text(file_bytes)}, more than {MAX_RATIO} times its size; refused as a decompression "
                          f"bomb{declared.hint} (LENSLAB_MAX_RATIO raises the limit for a genuine flat image)")


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
