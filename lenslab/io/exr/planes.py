"""The channels of a half EXR made in the memory of the float32 image it was converted from, laid out as the
contiguous planes OpenEXR's bindings take, in that same memory."""

from __future__ import annotations

import numpy as np


def planes_after(halves: np.ndarray, image: np.ndarray) -> list[np.ndarray]:
    """The channels of ``halves`` (H x W x C float16 made by :func:`lenslab.io.halves.to_half` in place: the first
    half of the float32 ``image``'s memory) as contiguous planes in the second half of that memory, which holds
    exactly C planes of halves (no allocation of the image's size); planes of their own where ``halves`` is not so
    made."""
    h, w, c = halves.shape
    flat = image.reshape(-1).view(np.float16) if image.flags.c_contiguous and image.dtype == np.float32 else None
    if flat is None or halves.dtype != np.float16 or halves.size != image.size or not halves.flags.c_contiguous \
            or halves.ctypes.data != flat.ctypes.data:  # (float32 planes, or halves of their own memory)
        return [np.ascontiguousarray(halves[..., i]) for i in range(c)]
    spare = flat[halves.size:].reshape(c, h, w)  # (after the halves' last byte: nothing of them is overwritten)
    for i in range(c):
        spare[i] = halves[..., i]
    return list(spare)


__all__ = ["planes_after"]
