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
from typing import Any


def probe(path: str | os.PathLike, fmt: str) -> dict[str, Any]:
    """The structure of an image file, as ``lenslab info`` shows it, without reading its pixels.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    fmt : str
        Its format, a name of ``lenslab info --formats`` (:func:`lenslab.io.sniff` tells it).

    Returns
    -------
    dict
        ``file_bytes``, and by format: EXR ``parts`` (each with its storage, compression, data and display
        windows, channels with their pixel types, layers and attributes), TIFF ``pages`` (shape, axes,
        dtype, compression, photometric, planar layout, extra samples), Radiance HDR ``header`` and
        ``resolution``. Other formats give ``file_bytes`` only.

    Raises
    ------
    lenslab.errors.FormatError
        A header the format's library cannot read.
    OSError
        A file that cannot be opened.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np, lenslab
    >>> from lenslab.io import sniff
    >>> from lenslab.io.probe import probe
    >>> path = lenslab.write(pathlib.Path(tempfile.mkdtemp()) / "a.exr", np.ones((2, 4, 3)), pixel_type="float")
    >>> part = probe(path, sniff(path))["parts"][0]
    >>> part["data_window"], [(c["name"], c["type"]) for c in part["channels"]]
    ([0, 0, 3, 1], [('B', 'float'), ('G', 'float'), ('R', 'float')])
    """
    from lenslab.io.registry import get

    p = Path(path)
    out = {"file_bytes": p.stat().st_size}
    hook = get(fmt).probe
    if hook is not None:
        out.update(hook(p))
    return out
