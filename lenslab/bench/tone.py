"""Tone curve throughput: megapixels per second per curve on a float32 RGB image (4096 x 2048 unless
--quick), as a ratio against numpy.clip(image, 0, 1) on the same array in the same run.

The test image is a lognormal HDR field (median 0.18, a few stops of spread) with a small sun near
30000. Every per-pixel curve aims to stay within 4x of the numpy.clip floor, in both modes; each row prints its figure, the aim and whether it is met, and
--json writes them (keys ``tone.<curve>.<mode>``). Each figure's baseline is
re-measured alternately with it (best of N each), so a change in the machine's load between rows
does not skew the ratios. The luminance mode runs two ways with the same bits
(:func:`lenslab.tone.sweep.compiled_ready`): the compiled passes of a process that has numba loaded (a
batch, a warp with --tone; keys ``tone.<curve>.luminance``, with the aim) and the NumPy passes of a
command that tone-maps one image and does not load numba (keys ``tone.<curve>.luminance_numpy``, no
aim: there the start-up dominates; ``lenslab bench startup`` measures it). The OpenCV local operators (drago, mantiuk) are timed once each and are
much slower by nature.
"""

from __future__ import annotations

import argparse

AIM_RATIO = 4.0  # times numpy.clip(image, 0, 1) on the same array


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import add_tones_option, positive_int

    parser.add_argument("--quick", action="store_true", help="use a 1024 x 512 image (a few seconds in all)")

    add_tones_option(parser, default="", help="comma-separated curve names (default: every curve)")
    parser.add_argument("--repeat", type=positive_int, default=5, help="best of N runs per figure (default 5)")
    parser.add_argument("--no-local", action="store_true", help="skip the slow OpenCV local operators")
    parser.add_argument("--threads", type=positive_int, default=None,
                        help="threads tonemap may use (default: every core, as the commands do); "
                             "numpy.clip runs on one either way")


def test_image(width: int, height: int, seed: int = 0):
    """Lognormal HDR float32 RGB image with a small very bright sun."""
    import numpy as np

    rng = np.random.default_rng(seed)
    img = (0.18 * np.exp2(rng.normal(0.0, 2.0, (height, width, 3)))).astype(np.float32)
    r = max(2, height // 64)
    img[height // 4 - r: height // 4 + r, width // 3 - r: width // 3 + r] = 30000.0
    return img


def paired_best(fn, baseline, repeat: int) -> tuple[float, float]:
    """Best wall times of ``fn()`` and ``baseline()``, run alternately ``repeat`` times each."""
    import time

    best_fn = best_base = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        baseline()
        t1 = time.perf_counter()
        fn()
        t2 = time.perf_counter()
        best_base, best_fn = min(best_base, t1 - t0), min(best_fn, t2 - t1)
    return best_fn, best_base


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from lenslab.bench.results import figure, mark
    from lenslab.bench.timing import best_time, ratio_line
    from lenslab.tone import CURVES, get_curve, sweep, tonemap

    width, height = (1024, 512) if args.quick else (4096, 2048)
    img = test_image(width, height)
    mpix = width * height / 1e6
    names = [get_curve(n).name for n in args.curves.split(",") if n.strip()] or list(CURVES)
    repeat = max(1, args.repeat)
    threads = args.threads
    from lenslab.tone.sweep import available_cores

    used = available_cores() if threads is None else max(1, threads)

    def clip():
        return np.clip(img, 0, 1)

    tonemap(img[:8, :8], "hable", exposure="auto", mode="luminance")  # first-call imports stay out of the figures
    import lenslab.tone.luminance  # noqa: F401  (numba and the compiled passes, loaded as a batch has them)

    sweep.COMPILED_PASSES = True
    tonemap(img[:8, :8], "hable", mode="luminance")
    sweep.COMPILED_PASSES = None
    base = best_time(clip, repeat=repeat)
    print(f"tone curves on a {width} x {height} float32 RGB image ({mpix:.1f} MP), {used} thread(s); "
          "baseline numpy.clip(img, 0, 1), one thread")
    print(ratio_line("numpy.clip (baseline)", base, base, f"{mpix / base:8.1f} MP/s"))
    rows = []
    for name in names:
        kind = CURVES[name].kind
        if kind == "local" and args.no_local:
            continue
        for mode in (("per-channel",) if kind == "local" else ("per-channel", "luminance", "luminance-numpy")):
            label = name if kind == "local" else f"{name} [{mode}]"
            key = f"tone.{name}" if kind == "local" else f"tone.{name}.{mode.replace('-', '_')}"
            passes = {"luminance": True, "luminance-numpy": False}.get(mode)

            def fn(name=name, mode=mode, passes=passes):
                sweep.COMPILED_PASSES = passes
                try:
                    return tonemap(img, name, mode=mode.replace("-numpy", ""), threads=threads)
                finally:
                    sweep.COMPILED_PASSES = None
            rows.append((key, label, fn, kind == "local", mode != "luminance-numpy"))
    rows.append(("tone.hable.per_channel_auto_exposure", "hable [per-channel] exposure=auto",
                 lambda: tonemap(img, "hable", exposure="auto", threads=threads), False, True))
    for key, label, fn, local, aimed in rows:
        t, b = paired_best(fn, clip, 1 if local else repeat)
        ok = figure(key, f"tone {label} vs numpy.clip", t / b, "x", aim=AIM_RATIO if aimed and not local else None,
                    note=f"{width}x{height} float32 RGB, {used} thread(s), {mpix / t:.1f} MP/s")
        print(ratio_line(label, t, b, f"{mpix / t:8.1f} MP/s  {mark(ok)}"))
    return 0
