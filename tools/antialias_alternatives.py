"""Measure how close the texture-filtering alternatives to ``--antialias`` come to its reference: the box
average of the bilinear source over each output pixel (``lenslab.bench.warp_reference``, 16 x 16 strata).

    python tools/antialias_alternatives.py [--hdri ../shared/data/hdri] [--json out.json]

The case is the accuracy case of ``lenslab bench warp``: every panorama (1024 x 512) into a 256 x 256
180-degree equidistant fisheye. The relative L1 error is taken over the pixels lying whole inside the
fisheye's circle whose footprint spans at most 6 texels each way (the rim and the footprints near the poles,
which every method treats apart, are left out, so the methods are compared on the same pixels: 74% of them).

Methods, each written here from its published form, on level 0 of the source, in float64:

- **Gaussian EWA, moment-matched**: texel weights ``exp(-q / 2)``, ``q = d^T S^-1 d`` for a texel at ``d``
  from the footprint's centre, with ``S = (a a^T + b b^T) / 12 + I / 6``: the covariance of the box over the
  parallelogram with sides ``a``, ``b`` (the map's derivatives across one output pixel) convolved with the
  bilinear tent. It is the Gaussian closest to the reference's kernel; cut at ``q < 9`` (3 sigma).
- **EWA as pbrt-v4 writes it** (``MIPMap::EWA``, Heckbert's ellipse with one texel added for the
  reconstruction): ``A = ay^2 + by^2 + 1``, ``B = -2 (ax ay + bx by)``, ``C = ax^2 + bx^2 + 1``, scaled by
  ``1 / (A C - B^2 / 4)``; weights ``exp(-2 r2) - exp(-2)`` for ``r2 = A s^2 + B s t + C t^2 < 1``.
- lenslab's own 2 x 2 and 4 x 4 supersampling and ``--antialias`` through ``lenslab.warp.warp``.

One run over the eight panoramas takes about 15 minutes of one core (the references).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

#: the panoramas beside the repository (../shared/data/hdri)
DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "hdri"
SIZE, FOV, REACH = 256, 180.0, 6  # output side, fisheye field, texels a footprint may span each way


def source_position(x, y, w, h):
    """Source texel coordinates (pixel centres at whole numbers) of fisheye points ``x``, ``y`` (float64)."""
    u, v = 2.0 * x / SIZE - 1.0, 1.0 - 2.0 * y / SIZE
    r = np.hypot(u, v)
    a = r * np.radians(FOV) / 2.0
    s = np.where(r > 0, np.sin(a) / np.maximum(r, 1e-300), 1.0)
    dx, dy, dz = s * u, s * v, np.cos(a)
    lon, lat = np.arctan2(dx, dz), np.arctan2(dy, np.hypot(dx, dz))
    return (lon / np.pi + 1.0) * w / 2.0 - 0.5, (1.0 - lat / (np.pi / 2.0)) * h / 2.0 - 0.5


def texels(img, j, i):
    """Texels at integer rows ``j``, columns ``i``: the seam wrapped, rows folded across the poles."""
    h, w = img.shape[:2]
    top, bottom = j < 0, j >= h
    jj = np.where(top, -1 - j, np.where(bottom, 2 * h - 1 - j, j))
    ii = np.where(top | bottom, i + w // 2, i) % w
    return img[jj, ii].astype(np.float64)


def footprints(w, h):
    """Each pixel's centre (cx, cy) and sides a = (ax, ay), b = (bx, by) in texels (central differences)."""
    y, x = np.mgrid[0:SIZE, 0:SIZE] + 0.5
    cx, cy = source_position(x, y, w, h)
    xp, yp = source_position(x + 0.5, y, w, h)
    xm, ym = source_position(x - 0.5, y, w, h)
    ax, ay = (xp - xm + w / 2) % w - w / 2, yp - ym
    xp, yp = source_position(x, y + 0.5, w, h)
    xm, ym = source_position(x, y - 0.5, w, h)
    bx, by = (xp - xm + w / 2) % w - w / 2, yp - ym
    return cx, cy, ax, ay, bx, by


def ewa(img, weight_of):
    """Normalised weighted sum over the texels within REACH of each centre; weight_of gives the weights."""
    h, w = img.shape[:2]
    cx, cy, ax, ay, bx, by = footprints(w, h)
    i0, j0 = np.round(cx).astype(np.int64), np.round(cy).astype(np.int64)
    out = np.zeros((SIZE, SIZE, img.shape[2]))
    total, taps = np.zeros((SIZE, SIZE)), np.zeros((SIZE, SIZE))
    for dj in range(-REACH, REACH + 1):
        for di in range(-REACH, REACH + 1):
            s, t = i0 + di - cx, j0 + dj - cy
            wt = weight_of(s, t, ax, ay, bx, by)
            taps += wt > 0
            out += wt[..., None] * texels(img, j0 + dj, i0 + di)
            total += wt
    with np.errstate(invalid="ignore", divide="ignore"):
        return out / total[..., None], taps


def moment_matched(s, t, ax, ay, bx, by):
    sxx = (ax * ax + bx * bx) / 12.0 + 1.0 / 6.0
    syy = (ay * ay + by * by) / 12.0 + 1.0 / 6.0
    sxy = (ax * ay + bx * by) / 12.0
    det = sxx * syy - sxy * sxy
    q = (syy * s * s - 2.0 * sxy * s * t + sxx * t * t) / det
    return np.where(q < 9.0, np.exp(-0.5 * q), 0.0)


def pbrt_v4(s, t, ax, ay, bx, by):
    a, b, c = ay * ay + by * by + 1.0, -2.0 * (ax * ay + bx * by), ax * ax + bx * bx + 1.0
    r2 = (a * s * s + b * s * t + c * t * t) / (a * c - b * b / 4.0)
    return np.where(r2 < 1.0, np.exp(-2.0 * r2) - np.exp(-2.0), 0.0)


def measure(path: Path) -> dict:
    from lenslab.bench.warp import _read
    from lenslab.bench.warp_reference import reference
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    img = _read(path)
    h, w = img.shape[:2]
    ref = reference(img, SIZE, FOV)
    y, x = np.mgrid[0:SIZE, 0:SIZE] + 0.5
    cx, cy, ax, ay, bx, by = footprints(w, h)
    inside = np.hypot(2.0 * x / SIZE - 1.0, 1.0 - 2.0 * y / SIZE) < 1.0 - 2.5 / SIZE
    small = (np.abs(ax) + np.abs(bx) <= REACH) & (np.abs(ay) + np.abs(by) <= REACH)
    mask = inside & small
    total = np.abs(ref[mask]).sum()
    src, dst = Camera.from_spec("equirect", (w, h)), Camera.from_spec(f"fisheye:fov={FOV:g}", (SIZE, SIZE))
    row = {"panorama": path.stem, "pixels": float(mask.mean())}
    for key, kw in (("antialias", {"antialias": True}), ("ss2x2", {"samples": 4}), ("ss4x4", {"samples": 16})):
        out = warp(img, src, dst, **kw)[0].astype(np.float64)
        row[key] = 100.0 * np.abs(out[mask] - ref[mask]).sum() / total
    for key, fn in (("ewa_moment_matched", moment_matched), ("ewa_pbrt_v4", pbrt_v4)):
        out, taps = ewa(img, fn)
        row[key] = 100.0 * np.abs(out[mask] - ref[mask]).sum() / total
        row[key + "_taps"] = float(taps[mask].mean())
    return row


def build_parser() -> argparse.ArgumentParser:
    from lenslab.jobs.arguments import ArgumentParser  # one-line errors, no abbreviated options

    parser = ArgumentParser(prog="python tools/antialias_alternatives.py", description=__doc__.splitlines()[0])
    parser.add_argument("--hdri", type=Path, default=DATA, help="folder of the panoramas (*.exr)")
    parser.add_argument("--json", type=Path, help="also write the figures to this file")
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    paths = sorted(args.hdri.glob("*.exr"))
    if not paths:
        print(f"antialias_alternatives.py: no panorama (*.exr) in {args.hdri}", file=sys.stderr)
        return 1
    rows = []
    print("relative L1 vs the 16x16 box reference, %   (taps: texels with weight, mean)")
    for path in paths:
        r = measure(path)
        rows.append(r)
        print(f"{r['panorama']:<10s} --antialias {r['antialias']:6.3f}  ss2x2 {r['ss2x2']:6.3f}  ss4x4 {r['ss4x4']:6.3f}"
              f"  EWA moment-matched {r['ewa_moment_matched']:6.3f} ({r['ewa_moment_matched_taps']:.1f} taps)"
              f"  EWA pbrt-v4 {r['ewa_pbrt_v4']:6.3f} ({r['ewa_pbrt_v4_taps']:.1f} taps)", flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
