"""Outputs made of pieces that are cameras of their own (tiles): which cameras they are, and rendering
one plan into a tile's region of the whole output (:func:`lenslab.warp.multiview.warp_tiles`)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses import Camera, Pose


def render_region(plan, src, out, alpha, x0: int, y0: int, progress, alpha_channel: bool | None = None) -> None:
    """Render ``plan`` (a :class:`lenslab.warp.WarpPlan`) into the region of ``out``/``alpha`` at (x0, y0) (zeros, or
    what undrawn pixels are to keep), into those pixels themselves: a band of a region narrower than the output is
    drawn in scratch memory and copied in (:class:`lenslab.warp.kernels.dispatch.contiguous_rows`), so no buffer of
    the region's size is made (a stereo output's eye is half the output). ``alpha_channel``: whether the image
    carries alpha (:func:`lenslab.io.alpha.alpha_last`)."""
    h, w = plan.out_shape
    region = slice(y0, y0 + h), slice(x0, x0 + w)
    plan.render(src, out[region], alpha[region], progress, alpha_channel=alpha_channel)


def band_count(plan) -> int:
    """The bands ``plan`` (a :class:`lenslab.warp.WarpPlan`) reports to its ``progress`` as it renders them, one call
    each: its own, every part's (the tiles or eyes of its output, each with its own bands), or its G plan's (a lens
    with per-channel optics, whose G plan alone reports)."""
    if plan.parts is not None:
        return sum(band_count(part) for _, _, part, _ in plan.parts)
    if plan.channels is not None:
        return band_count(plan.channels[1])
    return len(plan.band_rows())


def has_camera_pieces(camera: Camera) -> bool:
    """Whether the camera's image is made of pieces that are cameras of their own (tiles)."""
    pieces = camera.lens.pieces()
    return len(pieces) > 1 and any(p.lens is not None for p in pieces)


def tile_cameras(camera: Camera) -> list[tuple[int, int, Camera | None]]:
    """``(x0, y0, camera)`` of every piece of a camera whose pieces are cameras of their own (tiles), in
    order (None for a piece with no camera).

    Each piece camera has the piece's lens, its rotation composed with the whole camera's, and its eye
    placed in the world.
    """
    out = []
    for piece in camera.lens.pieces():
        x0, y0 = int(piece.x0), int(piece.y0)
        if piece.lens is None:
            out.append((x0, y0, None))
            continue
        rot = camera.pose.rotation @ piece.pose.rotation
        eye = camera.pose.eye + camera.pose.rotation @ piece.pose.eye
        out.append((x0, y0, Camera(piece.lens, Pose(rot, eye))))
    return out


__all__ = ["has_camera_pieces", "render_region", "tile_cameras"]
