"""Stereo frames in a warp: each output eye from the same eye of the source.

A lens whose :meth:`~lenslab.lenses.core.base.Lens.pieces` carry ``eye`` numbers holds two eyes in one
frame (``stereo:sbs,...``). The engine never asks which model that is; it pairs the eyes:

- stereo -> stereo: output eye ``k`` from source eye ``k``, each read from its own half only;
- mono -> stereo: both output eyes from the one source;
- stereo -> mono: the output from the source's first eye (left or top), as ffmpeg's v360 does.
"""

from __future__ import annotations

from lenslab.lenses import Camera


def eye_pieces(lens) -> list:
    """The pieces of ``lens`` that are eyes of a stereo frame, in eye order (empty for a mono lens)."""
    return sorted((p for p in lens.pieces() if p.eye is not None and p.lens is not None), key=lambda p: p.eye)


def eye_pairs(src: Camera, dst: Camera):
    """``[(x0, y0, crop, src_camera, dst_camera), ...]``: one warp per output eye (``crop`` = the source
    rectangle ``(x0, y0, w, h)`` it reads, or None for the whole source), or None when neither camera
    is stereo."""
    s_eyes, d_eyes = eye_pieces(src.lens), eye_pieces(dst.lens)
    if not s_eyes and not d_eyes:
        return None
    outs = [(int(p.x0), int(p.y0), Camera(p.lens, dst.pose)) for p in d_eyes] or [(0, 0, dst)]
    pairs = []
    for k, (x0, y0, d_cam) in enumerate(outs):
        if s_eyes:
            p = s_eyes[min(k, len(s_eyes) - 1)]
            crop = (int(p.x0), int(p.y0), p.lens.width, p.lens.height)
            s_cam = Camera(p.lens, src.pose)
        else:
            crop, s_cam = None, src
        pairs.append((x0, y0, crop, s_cam, d_cam))
    return pairs


def crop_source(src, crop):
    """The source rectangle an eye reads (a contiguous float32 copy), or the whole source."""
    if crop is None:
        return src
    import numpy as np

    x0, y0, w, h = crop
    return np.ascontiguousarray(src[y0:y0 + h, x0:x0 + w])


__all__ = ["eye_pairs", "eye_pieces", "crop_source"]
