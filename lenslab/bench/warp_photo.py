"""A photo placed in a panorama: one-shot bilinear against ``cv2.remap`` of the same map, one thread.

A 2040x1536 float RGB pinhole photo (``perspective:fov=71.5``, the 4:3 frame of a phone's main camera; the
source of :mod:`lenslab.bench.warp` cut to that size) into a 3540x1770 equirect, turned 30 degrees right and 10 up:
the photo covers about 4% of the panorama, and every other output pixel has no source pixel. The map of
``cv2.remap`` is the exact map (:func:`lenslab.warp.exact_map`) computed beforehand, -10 where the photo does not
see (remap's constant border). Figures are CPU times (``time.process_time``, best of ``--repeat``, the two cases
interleaved) and their ratio, measured in the same run; aim: the one-shot warp (its map included) within 2x.
"""

from __future__ import annotations

SIZE, OUT = (2040, 1536), (3540, 1770)


def photo_speed(args, source) -> None:
    """Print and record the one-shot warp's CPU time over cv2.remap's (``source()``: a float32 RGB image at least
    2040 x 1536)."""
    import cv2
    import numpy as np

    from lenslab.bench.results import figure, mark
    from lenslab.bench.warp_filters import cpu_best
    from lenslab.lenses import Camera
    from lenslab.warp import exact_map, warp
    from lenslab.warp.kernels.dispatch import default_threads, set_threads

    img = np.ascontiguousarray(source()[:SIZE[1], :SIZE[0]])
    src = Camera.from_spec("perspective:fov=71.5", SIZE, yaw=30.0, pitch=10.0)
    dst = Camera.from_spec("equirect", OUT)
    xy, valid = exact_map(src, dst, dst.pixel_grid()[..., 0, :])
    mx = np.where(valid, xy[..., 0] - 0.5, -10.0).astype(np.float32)
    my = np.where(valid, xy[..., 1] - 0.5, -10.0).astype(np.float32)
    del xy
    cv2.setNumThreads(1)
    set_threads(1)
    try:
        cases = [("cv2.remap", lambda: cv2.remap(img, mx, my, cv2.INTER_LINEAR)),
                 ("one-shot bilinear (map included)", lambda: warp(img, src, dst))]
        best = cpu_best(cases, args.repeat)
    finally:
        cv2.setNumThreads(default_threads())
        set_threads(default_threads())
    base, ours = best["cv2.remap"], best["one-shot bilinear (map included)"]
    print(f"photo into a panorama: {SIZE[0]}x{SIZE[1]} perspective:fov=71.5 -> {OUT[0]}x{OUT[1]} equirect "
          f"({valid.mean():.1%} of it seen), one thread, CPU time, best of {args.repeat}")
    figure("warp.photo_remap_ms", f"photo into a panorama ({SIZE[0]}x{SIZE[1]} -> {OUT[0]}x{OUT[1]}): cv2.remap, "
           "one thread, CPU", base * 1e3, "ms")
    ok = figure("warp.photo_one_shot", "photo into a panorama, one-shot vs cv2.remap, one thread", ours / base, "x",
                aim=2.0)
    print(f"  cv2.remap {base * 1e3:.1f} ms, one-shot bilinear (map included) {ours * 1e3:.1f} ms: "
          f"{ours / base:.2f}x   aim <= 2x  {mark(ok)}")
