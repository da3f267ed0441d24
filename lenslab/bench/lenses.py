"""Lens throughput: directions per second for pixel_to_dir and dir_to_pixel of each model on a
2048 x 2048 grid of pixel centres (--size to change), as a ratio against plain NumPy evaluating the
equirect formula on the same grid in the same run (forward: phi, theta -> d; inverse: two atan2).

dir_to_pixel is fed each model's own output directions. Each figure is timed interleaved with its
baseline (the machine's load varies), best of --repeat runs of each. The aim is every model within 3x
of the baseline, except the numerically inverted sides (marked "solve"): the division-model
distortions' dir_to_pixel, the Brown polynomial's pixel_to_dir and the seed fisheye's dir_to_pixel,
which run a compiled bracketed Newton iteration per element (the seed fisheye's needs four
transcendental functions per step, about 5x), and the calibrated cameras' solved sides (OpenCV's and
Kannala-Brandt's undistortion, with a 2-D Newton for tangential terms, and OCamCalib's direction ->
pixel), printed with the largest iteration count they needed; and the tiled grid's dir_to_pixel, which searches its
tiles in order for the first that sees each direction (about 6x for 2x2).
"""

from __future__ import annotations

import argparse

DEFAULT_SPECS = (
    "equirect",
    "equirect:lon_min=-90,lon_max=90,lat_min=-45,lat_max=45",
    "perspective:fov=90",
    "fisheye:fov=180,mapping=equidistant",
    "fisheye:fov=180,mapping=equisolid",
    "fisheye:fov=180,mapping=stereographic",
    "fisheye:fov=180,mapping=orthographic",
    "tan-fisheye:fov=120",
    "cubemap:layout=3x2",
    "cubemap:layout=6x1",
    "swirl:amount=6",
    "pincushion:k1=0.3,k2=0.05,fov=90",
    "barrel:k1=-0.3,fov=90",
    "brown:k1=-0.05,fov=90",
    "tiled:2x2",
    "cubemap:layout=4x3",
    "eac",
    "dual-fisheye:fov=190",
    "cylindrical",
    "cylindrical-equal-area",
    "mercator",
    "pannini",
    "hammer",
    "sinusoidal",
    "little-planet",
    "fisheye:dfov=180",
    # calibrated cameras (numbers of a 1024-px calibration, scaled to the grid)
    "opencv:fx=600,fy=600,cx=511.5,cy=511.5,k1=-0.28,k2=0.09,k3=-0.01,k4=0.02,k5=0.001,k6=0.0005,width=1024,height=1024",
    "opencv:fx=600,fy=600,cx=511.5,cy=511.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=-0.01,k4=0.02,k5=0.001,"
    "k6=0.0005,s1=0.001,s2=-0.0002,s3=0.0007,s4=0.0001,width=1024,height=1024",
    "kannala-brandt:fx=250,fy=250,cx=511.5,cy=511.5,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,width=1024,height=1024",
    "omnidir:fx=400,fy=400,cx=511.5,cy=511.5,xi=1.6,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,width=1024,height=1024",
    "double-sphere:fx=200,fy=200,cx=511.5,cy=511.5,xi=-0.2,alpha=0.6,width=1024,height=1024",
    "eucm:fx=200,fy=200,cx=511.5,cy=511.5,alpha=0.6,beta=1.1,width=1024,height=1024",
    "ocam:pol=-250 0 0.002,xc=511.5,yc=511.5,width=1024,height=1024",
    "devernay-fov:fx=400,fy=400,cx=511.5,cy=511.5,omega=0.9,width=1024,height=1024",
)

#: every closed-form side within this ratio of the NumPy equirect baseline
AIM = 3.0

#: (model name, direction) pairs solved numerically
SOLVED = {("pincushion", "d2p"), ("barrel", "d2p"), ("distortion", "d2p"), ("brown", "p2d"), ("tan-fisheye", "d2p"),
          ("opencv", "p2d"), ("kannala-brandt", "p2d"), ("omnidir", "p2d"), ("ocam", "d2p")}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--size", type=positive_int, default=2048, help="grid side in pixels (default 2048)")
    parser.add_argument("--repeat", type=positive_int, default=3, help="best of N runs per figure (default 3)")
    parser.add_argument("--models", default="", help="semicolon-separated lens specs (default: one or more per model)")


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from lenslab.bench.results import figure, mark as met_word
    from lenslab.bench.timing import best_time, ratio_line
    from lenslab.lenses import make_lens

    n = int(args.size)
    repeat = max(1, int(args.repeat))
    specs = [s.strip() for s in args.models.split(";") if s.strip()] or list(DEFAULT_SPECS)
    ys, xs = np.mgrid[0:n, 0:n].astype(np.float64) + 0.5
    xy = np.stack([xs, ys], axis=-1)
    del xs, ys
    count = n * n

    def equirect_forward():
        phi = (2.0 * xy[..., 0] / n - 1.0) * np.pi
        theta = (1.0 - 2.0 * xy[..., 1] / n) * (np.pi / 2)
        ct = np.cos(theta)
        return np.stack([ct * np.sin(phi), np.sin(theta), ct * np.cos(phi)], axis=-1)

    dirs0 = equirect_forward()

    def equirect_inverse():
        phi = np.arctan2(dirs0[..., 0], dirs0[..., 2])
        theta = np.arctan2(dirs0[..., 1], np.hypot(dirs0[..., 0], dirs0[..., 2]))
        return np.stack([(phi / np.pi + 1.0) * (0.5 * n), (1.0 - theta / (np.pi / 2)) * (0.5 * n)], axis=-1)

    # the machine is shared and its load varies: each figure is timed interleaved with its baseline
    # (model, baseline, model, baseline, ...), and the ratio is of the best of each, so both come from
    # the same stretch of time
    def paired(fn, base_fn):
        t_best = b_best = float("inf")
        for _ in range(repeat):
            t_best = min(t_best, best_time(fn, repeat=1))
            b_best = min(b_best, best_time(base_fn, repeat=1))
        return t_best, b_best

    print(f"lens models on a {n} x {n} grid ({count / 1e6:.1f} M directions); each figure against plain NumPy "
          f"equirect timed alongside it (best of {repeat}, interleaved)")
    base_f = best_time(equirect_forward, repeat=repeat)
    base_i = best_time(equirect_inverse, repeat=repeat)
    print(ratio_line("baseline forward (pixel -> dir)", base_f, base_f, f"{count / base_f / 1e6:7.1f} Mdir/s"))
    print(ratio_line("baseline inverse (dir -> pixel)", base_i, base_i, f"{count / base_i / 1e6:7.1f} Mdir/s"))
    worst: dict[str, tuple[float, str]] = {}
    within: dict[str, int] = {}
    total: dict[str, int] = {}
    for spec in specs:
        lens = make_lens(spec, (n, n))
        t_f, b_f = paired(lambda: lens.pixel_to_dir(xy), equirect_forward)
        dirs, valid = lens.pixel_to_dir(xy)
        t_i, b_i = paired(lambda: lens.dir_to_pixel(dirs), equirect_inverse)
        del dirs, valid
        for label, t, base, key in (("p2d", t_f, b_f, "p2d"), ("d2p", t_i, b_i, "d2p")):
            mark = "  (solve)" if (lens.name, key) in SOLVED else ""
            its = getattr(lens, "solver_iterations", {}).get(key) if mark else None
            if its:  # calibrated models state the largest iteration count their solve needed
                mark = f"  (solve, <= {its} iterations)"
            solved = bool(mark)
            short = spec if len(spec) <= 40 else spec[:37] + "..."
            ok = figure(f"lenses.{spec}.{key}", f"{short} {label}", t / base, "x", aim=None if solved else AIM,
                        note=mark.strip(" ()"), detail=not solved)
            print(ratio_line(f"{spec[:34]} {label}", t, base,
                             f"{count / t / 1e6:7.1f} Mdir/s{mark} {met_word(ok)}".rstrip()), flush=True)
            if not solved:
                within[key] = within.get(key, 0) + (t / base <= AIM)
                total[key] = total.get(key, 0) + 1
                if t / base > worst.get(key, (0.0, ""))[0]:
                    worst[key] = (t / base, lens.name)
    for key, words in (("p2d", "pixel -> dir"), ("d2p", "dir -> pixel")):
        if key in worst:
            ratio, name = worst[key]
            ok = figure(f"lenses.worst.{key}", f"{words}, slowest closed-form model vs NumPy equirect", ratio,
                        "x", aim=AIM, note=f"{name}; {within[key]} of {total[key]} specs within {AIM:g}x")
            print(f"slowest closed-form {words}: {name} {ratio:.2f}x {met_word(ok)}")
    return 0
