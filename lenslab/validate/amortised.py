"""The amortised trade: K views from one panorama render plus K warps, against K direct renders.

The views cycle through four kinds: a 180 deg fisheye, a swirl, a pincushion-distorted perspective and
a 2x2 tiled grid of views sharing one eye; view ``i`` is kind ``i mod 4`` turned by ``90 deg * (i // 4)``
of yaw, so K = 16 is each kind looking four ways.

At **equal error**: for each kind the warp's relative L1 against a high-sample reference is measured
(in Monte Carlo mode less the reference's own noise floor, from two half renders, so both routes are
judged by the error they carry themselves); the direct render is measured at a few sample counts and
its error fitted as a power law of the samples per pixel (``e = e1 spp^-p``, ``p = 1/2`` for Monte
Carlo noise, at least 1/4 to keep a flat fit from extrapolating without bound); the samples the direct
render needs to match the warp's error follow, and its time from a linear fit ``t0 + t1 spp`` of its
measured times. Counts beyond 4x the largest measured one are flagged ``extrapolated``. The panorama
route costs one panorama render plus K warps.
"""

from __future__ import annotations

import time
from typing import Any, Sequence

import numpy as np

from lenslab import metrics
from lenslab.lenses import Camera

# (name, lens spec) of the four view kinds; the tiled grid's tiles share the panorama's eye
VIEW_KINDS: tuple[tuple[str, str], ...] = (
    ("fisheye", "fisheye:fov=180,mapping=equisolid"),
    ("swirl", "swirl:amount=6"),
    ("pincushion", "pincushion:k1=0.3,k2=0.05,fov=90"),
    ("tiled 2x2", "tiled:2x2"),
)


def view_camera(kind: int, size: tuple[int, int], eye=(0.0, 0.0, 0.0), yaw0: float = 0.0, turn: int = 0,
                pitch: float = 0.0, specs: Sequence[tuple[str, str]] = VIEW_KINDS) -> Camera:
    _, spec = specs[kind % len(specs)]
    return Camera.from_spec(spec, size, yaw=yaw0 + 90.0 * turn, pitch=pitch, eye=eye)


def fit_spp_power(spps: Sequence[int], errs: Sequence[float]) -> tuple[float, float]:
    """Least-squares fit ``log e = log e1 - p log spp``; returns (e1, p) with p >= 0.05."""
    x = np.log(np.asarray(spps, dtype=np.float64))
    y = np.log(np.asarray(errs, dtype=np.float64))
    if len(x) < 2 or np.ptp(x) == 0:
        return float(np.exp(y.mean())), 0.5
    p, c = np.polyfit(x, y, 1)
    return float(np.exp(c)), float(max(-p, 0.05))


def amortised(source, pano_size: tuple[int, int], view_size: tuple[int, int], setting, warp_fn=None,
              spp: int = 1, reference_spp: int = 64, direct_spp: Sequence[int] = (1, 4, 16),
              ks: Sequence[int] = (1, 4, 16), seed: int | None = 0, eye=(0.0, 0.0, 0.0), yaw0: float = 0.0,
              pitch: float = 0.0, specs: Sequence[tuple[str, str]] = VIEW_KINDS, repeat: int = 3,
              progress: bool = True) -> dict[str, Any]:
    """Measure the trade; returns a JSON-friendly dict with per-kind figures and one row per K."""
    from tqdm import tqdm

    from lenslab.validate.run import call_warp, panorama_camera, render_reference

    if warp_fn is None:
        from lenslab.validate.run import default_warp

        warp_fn = default_warp()
    noise_free = bool(getattr(source, "noise_free", False)) or seed is None
    pseed = None if noise_free else seed
    rseed = None if noise_free else seed + 1_000_003
    first = view_camera(0, view_size, eye, yaw0, 0, pitch, specs)
    pcam = panorama_camera(first, pano_size)
    pano = source.render(pcam, spp=spp, seed=pseed)
    kinds = []
    n_kinds = min(len(specs), max(ks))
    bar = tqdm(total=n_kinds, desc="amortised", unit="view", disable=not progress, leave=False)
    for k in range(n_kinds):
        cam = view_camera(k, view_size, eye, yaw0, 0, pitch, specs)
        ref, halves = render_reference(source, cam, reference_spp, None, rseed)
        mask = metrics.valid_mask(ref.alpha)
        noise = metrics.noise_floor_split(halves[0], halves[1], mask) if halves is not None else 0.0

        def error(img, alpha):
            # the error the image itself carries: measured L1 less the reference's own noise floor
            l1 = metrics.relative_l1(ref.image, img, metrics.valid_mask(ref.alpha, alpha))
            return max(l1 - noise, 0.01 * l1)

        best = float("inf")
        img = alpha = None
        for _ in range(max(1, repeat)):
            t0 = time.perf_counter()
            img, alpha = call_warp(warp_fn, pano.image, pcam, cam, setting)
            best = min(best, time.perf_counter() - t0)
        werr = error(img, alpha)
        dspp, derr, dsec = [], [], []
        for n in direct_spp:
            d = source.render(cam, spp=int(n), seed=pseed)
            dspp.append(int(n))
            derr.append(error(d.image, d.alpha))
            dsec.append(d.seconds)
        e1, p = fit_spp_power(dspp, derr)
        p = max(p, 0.25)  # no slower than spp^-1/4: keeps a flat fit from extrapolating without bound
        if len(dspp) >= 2 and np.ptp(dspp) > 0:
            t1, t0 = np.polyfit(np.asarray(dspp, float), np.asarray(dsec, float), 1)
        else:
            t1, t0 = dsec[0] / dspp[0], 0.0
        if t1 <= 0:
            t1, t0 = float(np.median(np.asarray(dsec) / np.asarray(dspp))), 0.0
        need = max(1.0, (e1 / werr) ** (1.0 / p)) if werr > 0 else float("inf")
        extrapolated = need > 4 * max(dspp)
        kinds.append({
            "kind": specs[k][0], "spec": cam.lens.spec(), "warp_seconds": best, "warp_l1": werr,
            "reference_spp": int(ref.spp), "reference_noise_l1": noise,
            "direct_spp": dspp, "direct_l1": derr, "direct_seconds": dsec,
            "direct_fit": {"e1": e1, "p": p, "t0": float(max(t0, 0.0)), "t1": float(t1)},
            "direct_spp_for_equal_error": need, "extrapolated": bool(extrapolated),
            "direct_seconds_for_equal_error": float(max(t0, 0.0) + t1 * need),
        })
        bar.update()
    bar.close()
    rows = []
    for K in ks:
        views = [kinds[i % len(kinds)] for i in range(K)]
        pano_total = pano.seconds + sum(v["warp_seconds"] for v in views)
        direct_total = sum(v["direct_seconds_for_equal_error"] for v in views)
        rows.append({"K": int(K), "panorama_route_seconds": pano_total, "direct_route_seconds": direct_total,
                     "speedup": direct_total / pano_total if pano_total > 0 else float("nan"),
                     "mean_l1": float(np.mean([v["warp_l1"] for v in views]))})
    return {"pano_size": list(pano_size), "view_size": list(view_size), "setting": setting.label,
            "panorama_spp": spp, "panorama_seconds": pano.seconds,
            "mode": "noise-free" if noise_free else "monte-carlo", "kinds": kinds, "rows": rows}


def markdown(res: dict[str, Any]) -> str:
    lines = [
        "## Amortised: K views from one panorama vs K direct renders at equal error",
        "",
        f"Panorama {res['pano_size'][0]}x{res['pano_size'][1]} ({res['panorama_spp']} spp, "
        f"{res['panorama_seconds']:.2f} s), warp setting {res['setting']}, views "
        f"{res['view_size'][0]}x{res['view_size'][1]}, {res['mode']} mode.",
        "",
        "| view | warp | warp rel. L1 (less reference noise) | direct spp for that error | direct time for it |",
        "|---|---|---|---|---|",
    ]
    for k in res["kinds"]:
        flag = " (extrapolated)" if k.get("extrapolated") else ""
        lines.append(f"| {k['kind']} | {k['warp_seconds'] * 1e3:.1f} ms | {100 * k['warp_l1']:.3f}% | "
                     f"{k['direct_spp_for_equal_error']:.1f}{flag} | {k['direct_seconds_for_equal_error']:.2f} s |")
    lines += ["", "| K | panorama + K warps | K direct renders | direct / panorama |", "|---|---|---|---|"]
    for r in res["rows"]:
        lines.append(f"| {r['K']} | {r['panorama_route_seconds']:.2f} s | {r['direct_route_seconds']:.2f} s | "
                     f"{r['speedup']:.2f}x |")
    return "\n".join(lines) + "\n"
