"""Per-channel optics and vignetting in a warp, as the lenses state them.

A lens with :meth:`~lenslab.lenses.core.base.Lens.channel_lenses` (chromatic aberration) is one lens per R,
G, B: the warp runs once per channel, channel ``c`` mapped from the source's channel lens ``c`` (or the
source lens) into the destination's channel lens ``c`` (or the destination lens); channels beyond
three and alpha follow G; an image with fewer than three channels is warped by the G lenses alone.

A lens with :meth:`~lenslab.lenses.core.base.Lens.falloff` (vignetting): as a destination the output is
multiplied by the falloff at each output pixel's centre; as a source the image is divided by its
falloff at each source pixel's centre (never by less than ``MIN_FALLOFF``) before it is sampled, so
every sample reads the light as it was before the lens dimmed it. Both are smooth across a pixel, so
one value per pixel stands for all its samples. Falloff dims light, not coverage: a trailing alpha
channel (only where the image carries one: :func:`lenslab.io.alpha.alpha_last`) is never multiplied or
divided by it.
"""

from __future__ import annotations

import numpy as np

from lenslab.io.alpha import colour_channels
from lenslab.lenses import Camera
from lenslab.lenses.core.protocol import MIN_FALLOFF

FALLOFF_ROWS = 256  # rows of pixel centres per call of a lens's falloff (bounds the float64 working set)


def channel_cameras(src: Camera, dst: Camera) -> list[tuple[Camera, Camera]] | None:
    """``[(source, destination)]`` cameras for R, G, B when either lens has channel lenses, else None."""
    sl, dl = src.lens.channel_lenses(), dst.lens.channel_lenses()
    if sl is None and dl is None:
        return None
    return [(src if sl is None else Camera(sl[c], src.pose), dst if dl is None else Camera(dl[c], dst.pose))
            for c in range(3)]


def falloff_image(lens) -> np.ndarray | None:
    """The lens's falloff at every pixel centre (float32 H x W), or None when it has none."""
    first = lens.falloff(np.array([[0.5, 0.5]]))
    if first is None:
        return None
    w, h = lens.width, lens.height
    out = np.empty((h, w), dtype=np.float32)
    xs = np.arange(w, dtype=np.float64) + 0.5
    for r0 in range(0, h, FALLOFF_ROWS):
        r1 = min(h, r0 + FALLOFF_ROWS)
        pts = np.stack(np.broadcast_arrays(xs[None, :], np.arange(r0, r1, dtype=np.float64)[:, None] + 0.5), -1)
        f = np.asarray(lens.falloff(pts), dtype=np.float64)
        out[r0:r1] = np.where(np.isfinite(f), f, 0.0)
    return out


def divide_by_falloff(src: np.ndarray, falloff: np.ndarray, alpha: bool | None = None) -> np.ndarray:
    """A copy of ``src`` (H x W x C float32) whose colour is divided by ``falloff`` (H x W), never by less
    than MIN_FALLOFF; a trailing alpha channel (:func:`lenslab.io.alpha.alpha_last`) is coverage, not light,
    and is kept."""
    out = src.copy()
    with np.errstate(over="ignore"):  # light beyond float32: inf here, clamped and reported by the engine
        out[..., colour_channels(src.shape[2], alpha)] /= np.maximum(falloff, np.float32(MIN_FALLOFF))[..., None]
    return out


def channel_groups(nc: int) -> list[list[int]]:
    """The image channels each of the R, G, B plans renders: R, then G with every channel beyond three,
    then B; all of them by G for an image with fewer than three channels."""
    if nc < 3:
        return [[], list(range(nc)), []]
    return [[0], [1] + list(range(3, nc)), [2]]


def render_channels(plans, src: np.ndarray, out: np.ndarray, alpha: np.ndarray, progress) -> None:
    """Render each channel group with its own plan; alpha from the G plan (progress reported by it)."""
    h, w = out.shape[:2]
    for c, (plan, chans) in enumerate(zip(plans, channel_groups(src.shape[2]))):
        if not chans:
            continue
        part = np.zeros((h, w, len(chans)), dtype=np.float32)
        part_alpha = np.zeros((h, w), dtype=np.float32)
        plan.render(np.ascontiguousarray(src[..., chans]), part, part_alpha, progress if c == 1 else None)
        out[..., chans] = part
        if c == 1:
            alpha[...] = part_alpha
