"""The separable filters' speed: one-shot Lanczos-3 and bicubic (Catmull-Rom) warps against ``cv2.remap``.

A 4096x2048 float RGB equirect (forest.exr enlarged, or a smooth random image without ``--data``) into a 1024x1024
180-degree fisheye, one thread. Each warp is one-shot (its map included) and reads the source at the exact
position, folding taps across the seam and the poles; the baselines are ``cv2.remap`` with INTER_LANCZOS4 (8x8
taps) and INTER_CUBIC (4x4), float32 maps computed beforehand, 1/32-pixel weight tables. Figures are CPU times
(``time.process_time``, best of ``--repeat``, every case once per round) and their ratios, measured in the same
run. No aim is set for them.
"""

from __future__ import annotations

import time


def cpu_best(cases, repeat: int) -> dict[str, float]:
    """Least CPU time in seconds of each ``(label, fn)``, every round timing each case once."""
    best = {label: float("inf") for label, _ in cases}
    for _ in range(max(1, repeat)):
        for label, fn in cases:
            t0 = time.process_time()
            fn()
            best[label] = min(best[label], time.process_time() - t0)
    return best


def filter_speed(args, source) -> None:
    """Print and record the Lanczos and bicubic one-shot warps' CPU time over cv2.remap's (``source()``: the
    4096x2048 float32 RGB image)."""
    import cv2
    import numpy as np

    from lenslab.bench.results import figure
    from lenslab.lenses import Camera
    from lenslab.warp import exact_map, warp
    from lenslab.warp.kernels.dispatch import default_threads, set_threads

    img = source()
    src = Camera.from_spec("equirect", (4096, 2048))
    dst = Camera.from_spec(args.dst, (1024, 1024))
    xy, valid = exact_map(src, dst, dst.pixel_grid()[..., 0, :])
    mx = np.where(valid, xy[..., 0] - 0.5, -10.0).astype(np.float32)
    my = np.where(valid, xy[..., 1] - 0.5, -10.0).astype(np.float32)
    cv2.setNumThreads(1)
    set_threads(1)
    pairs = [("lanczos", cv2.INTER_LANCZOS4, "INTER_LANCZOS4"), ("bicubic", cv2.INTER_CUBIC, "INTER_CUBIC")]
    cases = []
    for name, flag, flag_name in pairs:
        cases.append((f"cv2.remap {flag_name}", lambda f=flag: cv2.remap(img, mx, my, f)))
        cases.append((f"one-shot {name}", lambda n=name: warp(img, src, dst, filter=n)))
    warp(img[:64, :128], Camera.from_spec("equirect", (128, 64)), Camera.from_spec(args.dst, (64, 64)),
         filter="lanczos")  # first call outside the timings
    best = cpu_best(cases, min(args.repeat, 5))
    print(f"filters: 4096x2048 float RGB equirect -> 1024x1024 {args.dst}, one thread, CPU time, best of "
          f"{min(args.repeat, 5)}; cv2.remap with float32 maps computed beforehand, lenslab one-shot (map included)")
    for name, _, flag_name in pairs:
        base, ours = best[f"cv2.remap {flag_name}"], best[f"one-shot {name}"]
        figure(f"warp.{name}_remap_ms", f"cv2.remap {flag_name} 4096x2048 -> 1024x1024, one thread, CPU", base * 1e3,
               "ms")
        figure(f"warp.{name}_vs_remap", f"one-shot {name} vs cv2.remap {flag_name}, one thread, CPU", ours / base, "x")
        print(f"  {name:<8s} {ours * 1e3:8.1f} ms   cv2.remap {flag_name:<14s} {base * 1e3:7.1f} ms   "
              f"{ours / base:5.2f}x   no aim")
    set_threads(default_threads())
