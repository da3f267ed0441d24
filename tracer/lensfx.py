"""The lens's colour effects in a direct trace: a ray per channel (chromatic aberration) and the
relative illumination (vignetting) as each sample's weight.

A lens that has them answers ``channel_lenses()`` (one lens per R, G, B; G is the lens itself) and
``falloff(xy)``. The geometric rays (and the alpha) are the lens's own; red and blue are traced again
along their channel lens's rays through the same sub-pixel positions, and each sample's radiance is
multiplied by the falloff at its position. A warp through the same lens does the same per channel, so
the two can be compared.
"""

from __future__ import annotations

import numpy as np

from tracer.integrators import trace


def has_effects(lens) -> bool:
    channels = getattr(lens, "channel_lenses", None)
    falloff = getattr(lens, "falloff", None)
    return (channels is not None and channels() is not None) or (
        falloff is not None and falloff(np.zeros((1, 2))) is not None)


def apply_lens_effects(scene, camera, xy: np.ndarray, radiance: np.ndarray, rng, integrator: str,
                       max_depth: int, rr_depth: int, threads: int | None = 1) -> np.ndarray:
    """Radiance ``(N, 3)`` of samples at pixel positions ``xy`` (``(N, 2)``) traced along the lens's
    own rays, with red and blue retraced along their channel rays and the falloff applied (float32)."""
    lens = camera.lens
    channels = lens.channel_lenses() if hasattr(lens, "channel_lenses") else None
    if channels is not None:
        from lenslab.lenses import Camera

        for c in (0, 2):
            if channels[c] is lens:
                continue
            o, d, ok = Camera(channels[c], camera.pose).pixel_to_world(xy)
            col = np.zeros(len(xy), dtype=radiance.dtype)
            k = np.flatnonzero(ok)
            if len(k):
                col[k] = trace(scene, np.take(o, k, axis=0), np.take(d, k, axis=0), rng, integrator, max_depth,
                               rr_depth, threads=threads)[:, c]
            radiance[:, c] = col
    fall = lens.falloff(xy) if hasattr(lens, "falloff") else None
    if fall is not None:
        radiance *= np.asarray(fall, dtype=np.float64).reshape(-1, 1).astype(radiance.dtype)
    return radiance
