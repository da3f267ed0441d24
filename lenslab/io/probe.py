"""What a file holds beyond the pixels ``read`` returns, as ``lenslab info`` shows it: every EXR part, layer
and channel (pixel type, sampling), compression, windows and attributes; TIFF pages; the Radiance header;
video streams.

Each format plugin says how to probe its files (the ``probe`` hook of its
:class:`lenslab.io.plugin.Format` record); ``probe(path, fmt) -> dict`` (JSON-ready) asks the format
registry and adds the file's size. A probe never decodes more than it must.
"""

from __future__ import annotations

import os
from pathlib import Path


def probe(path: str | os.PathLike, fmt: str) -> dict:
    """The structure of the file at ``path`` of format ``fmt`` (a registry name): its size in bytes, then
    what the format's probe finds."""
    from lenslab.io.registry import get

    p = Path(path)
    out = {"file_bytes": p.stat().st_size}
    hook = get(fmt).probe
    if hook is not None:
        out.update(hook(p))
    return out
