"""Warps measured against a reference the user brings: their own render or photograph of the view.

Where :mod:`lenslab.validate.run` renders its reference, :func:`against_reference` takes one: the
reference image seen by the reference camera, a source image (a panorama, or any lens) with its camera,
and the warp settings to try. Each setting warps the source into the reference camera and is compared
with :func:`lenslab.metrics.diff.diff_images` (the report of ``lenslab diff``): only pixels that the
warp covers fully (and, when the reference has alpha, that it covers) count.
"""

from __future__ import annotations

import time
from typing import Any, Sequence

import numpy as np

from lenslab.lenses import Camera
from lenslab.metrics.diff import DiffReport, Thresholds, diff_images


def against_reference(reference: np.ndarray, ref_camera: Camera, source: np.ndarray, src_camera: Camera,
                      settings: Sequence, thresholds: Thresholds | None = None, flip: str = "auto",
                      allow_parallax: bool = False) -> list[dict[str, Any]]:
    """One row per setting: ``{"label", "seconds", "report": DiffReport, "image", "alpha"}``.

    ``reference`` is float32 ``H x W x C`` at ``ref_camera``'s size (C = 4: premultiplied alpha, as
    :func:`lenslab.io.read` gives it); ``settings`` are :class:`lenslab.validate.run.WarpSetting` values.
    """
    from lenslab.validate.run import ValidationError
    from lenslab.warp import WarpPlan

    ref = np.asarray(reference, dtype=np.float32)
    if ref.ndim == 2:
        ref = ref[..., None]
    if (ref.shape[1], ref.shape[0]) != tuple(ref_camera.size):
        raise ValidationError(f"the reference is {ref.shape[1]}x{ref.shape[0]} but its camera is "
                              f"{ref_camera.width}x{ref_camera.height}")
    colour = ref.shape[2] - 1 if ref.shape[2] in (2, 4) else ref.shape[2]
    rows = []
    for setting in settings:
        plan = WarpPlan(src_camera, ref_camera, filter=setting.filter, samples=setting.samples,
                        antialias=setting.antialias, allow_parallax=allow_parallax)
        t0 = time.perf_counter()
        out, coverage = plan.run(source)
        seconds = time.perf_counter() - t0
        out = out if out.ndim == 3 else out[..., None]
        test = out[..., :colour] if out.shape[2] >= colour else np.repeat(out[..., :1], colour, axis=-1)
        if test.shape[2] != colour:
            raise ValidationError(f"the source has {out.shape[2]} channels, the reference {colour} colour channels")
        warped = np.concatenate([test, coverage[..., None]], axis=-1)
        report: DiffReport = diff_images(ref, warped, thresholds=thresholds, flip=flip)
        rows.append({"label": setting.label, "seconds": seconds, "report": report, "image": test, "alpha": coverage})
    return rows


def best(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The row with the smallest RMS error (NaN last)."""
    return min(rows, key=lambda r: (not np.isfinite(r["report"].rms_error), r["report"].rms_error))


__all__ = ["against_reference", "best"]
