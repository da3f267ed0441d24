"""Choose the cheapest way to reach a target error: panorama size, warp setting and samples per pixel.

Two steps, both reported:

1. **From the table**: of the measured rows whose relative L1 is at or below the target, the one with
   the least total time (panorama render + warp).
2. **From a model** fitted to the table, per warp setting, when the table is too coarse (no row
   reaches the target, or the cheapest one overshoots it by a wide margin):

   - error ``l1(W, spp) = a W^-b + c spp^-1/2 + f``: a power law in the panorama width ``W`` for the
     resampling error, a Monte Carlo term in the panorama's samples per pixel (fitted only when more than
     one ``spp`` was measured, else folded into the floor ``f``), fitted in log space with nlopt (BOBYQA);
   - time ``t(W, spp) = t0 + t1 W^2 spp`` (tracing cost grows with the panorama's pixels and samples),
     a linear least-squares fit;
   - then nlopt (COBYLA) minimises ``t`` subject to ``l1 <= target`` over continuous ``W`` (and ``spp``
     when modelled), within a factor 2 of the measured range; ``W`` is rounded up to a multiple of 64
     with ``H = W/2``, and ``spp`` up to an integer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np


@dataclass
class ErrorModel:
    setting: str
    filter: str
    samples: int
    antialias: bool
    a: float
    b: float
    c: float
    floor: float
    t0: float
    t1: float
    fit_rms_log: float
    widths: list[int] = field(default_factory=list)
    spps: list[int] = field(default_factory=list)

    def error(self, width: float, spp: float) -> float:
        return self.a * width ** (-self.b) + self.c / math.sqrt(max(spp, 1e-9)) + self.floor

    def seconds(self, width: float, spp: float) -> float:
        return self.t0 + self.t1 * width * width * spp


def _group(rows: Sequence[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    g: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        if r.get("kind", "warp") == "warp" and np.isfinite(r.get("l1", np.nan)) and r["l1"] > 0:
            g.setdefault(r["setting"], []).append(r)
    return g


def fit_model(rows: Sequence[dict[str, Any]], error_key: str = "l1") -> ErrorModel | None:
    """Fit the error and time models to the rows of one warp setting (needs two panorama widths)."""
    import nlopt

    widths = np.array([r["pano_size"][0] for r in rows], dtype=np.float64)
    spps = np.array([r.get("spp", 1) for r in rows], dtype=np.float64)
    err = np.array([r[error_key] for r in rows], dtype=np.float64)
    secs = np.array([r["seconds"] for r in rows], dtype=np.float64)
    if len(np.unique(widths)) < 2:
        return None
    use_spp = len(np.unique(spps)) > 1
    w0 = float(np.median(widths))
    logerr = np.log(err)

    def model(p, w, s):  # p = (log a', b, log c, log f) with a' the error at w0
        return (math.exp(p[0]) * (w / w0) ** (-p[1])
                + (math.exp(p[2]) / np.sqrt(s) if use_spp else 0.0) + math.exp(p[3]))

    def objective(p, grad):
        pred = model(p, widths, spps)
        return float(np.sum((np.log(pred) - logerr) ** 2))

    lo_e = float(np.log(err.min() * 1e-6))
    hi_e = float(np.log(err.max() * 10.0))
    opt = nlopt.opt(nlopt.LN_BOBYQA, 4)
    opt.set_lower_bounds([lo_e, 0.0, lo_e, lo_e])
    opt.set_upper_bounds([hi_e, 4.0, hi_e, hi_e])
    opt.set_min_objective(objective)
    opt.set_xtol_rel(1e-8)
    opt.set_maxeval(4000)
    best, best_val = None, float("inf")
    for b0 in (0.5, 1.0, 2.0):  # a few starts: the floor and the slope trade off
        x0 = [float(np.log(err.max())), b0, float(np.log(err.min() * 0.1)), float(np.log(err.min() * 0.1))]
        try:
            x = opt.optimize(x0)
            v = opt.last_optimum_value()
        except (nlopt.RoundoffLimited, ValueError, RuntimeError):
            continue
        if v < best_val:
            best, best_val = x, v
    if best is None:
        return None
    # time: t0 + t1 * W^2 * spp, linear least squares (non-negative)
    A = np.stack([np.ones_like(widths), widths ** 2 * spps], axis=1)
    (t0, t1), *_ = np.linalg.lstsq(A, secs, rcond=None)
    if t1 <= 0:
        t1 = float(np.max(secs / (widths ** 2 * spps)))
        t0 = 0.0
    r0 = rows[0]
    a = math.exp(best[0]) * w0 ** best[1]
    return ErrorModel(r0["setting"], r0["filter"], int(r0["samples"]), bool(r0["antialias"]), a, float(best[1]),
                      math.exp(best[2]) if use_spp else 0.0, math.exp(best[3]), float(max(t0, 0.0)), float(t1),
                      math.sqrt(best_val / len(rows)), sorted({int(w) for w in widths}),
                      sorted({int(s) for s in spps}))


def solve(model: ErrorModel, target: float, max_width: float, max_spp: float) -> dict[str, Any] | None:
    """Cheapest continuous (width, spp) with predicted error <= target (nlopt COBYLA); None if unreachable."""
    import nlopt

    use_spp = model.c > 0
    lo_w = max(64.0, min(model.widths) / 2.0)
    lo_s, hi_s = 1.0, (max_spp if use_spp else 1.0)
    if model.error(max_width, hi_s) > target:
        return None
    n = 2 if use_spp else 1
    opt = nlopt.opt(nlopt.LN_COBYLA, n)
    opt.set_lower_bounds([lo_w] + ([lo_s] if use_spp else []))
    opt.set_upper_bounds([max_width] + ([hi_s] if use_spp else []))
    spp_fixed = float(model.spps[0]) if not use_spp else None

    def unpack(x):
        return float(x[0]), (float(x[1]) if use_spp else spp_fixed)

    opt.set_min_objective(lambda x, g: model.seconds(*unpack(x)) / max(model.seconds(max_width, hi_s), 1e-12))
    opt.add_inequality_constraint(lambda x, g: (model.error(*unpack(x)) - target) / target, 1e-6)
    opt.set_xtol_rel(1e-6)
    opt.set_maxeval(2000)
    x0 = [max_width] + ([hi_s] if use_spp else [])
    try:
        x = opt.optimize(x0)
    except (nlopt.RoundoffLimited, ValueError, RuntimeError):
        x = x0
    w, s = unpack(x)
    if model.error(w, s) > target * (1 + 1e-3):
        w, s = unpack(x0)
    wr = int(math.ceil(w / 64.0) * 64)
    sr = int(math.ceil(s - 1e-9))
    return {"setting": model.setting, "filter": model.filter, "samples": model.samples,
            "antialias": model.antialias, "pano_size": [wr, wr // 2], "spp": sr,
            "continuous_width": w, "continuous_spp": s,
            "predicted_l1": model.error(wr, sr), "predicted_seconds": model.seconds(wr, sr)}


def direct_alternative(rows: Sequence[dict[str, Any]], target: float, error_key: str = "l1"):
    """Samples per pixel a direct render of the target needs for ``target``, from the ``direct`` rows.

    Fits ``e = e1 spp^-p`` (least squares in log space) and ``t = t0 + t1 spp`` (least squares).
    """
    d = [r for r in rows if r.get("kind") == "direct" and np.isfinite(r.get(error_key, np.nan)) and r[error_key] > 0]
    if len(d) < 2:
        return None
    spp = np.array([r["spp"] for r in d], dtype=np.float64)
    err = np.array([r[error_key] for r in d], dtype=np.float64)
    sec = np.array([r["seconds"] for r in d], dtype=np.float64)
    if np.ptp(np.log(spp)) == 0:
        return None
    slope, icpt = np.polyfit(np.log(spp), np.log(err), 1)
    p = max(-slope, 0.05)
    need = max(1, int(math.ceil((math.exp(icpt) / target) ** (1.0 / p))))
    t1, t0 = np.polyfit(spp, sec, 1)
    if t1 <= 0:
        t1, t0 = float(np.median(sec / spp)), 0.0
    return {"spp": need, "predicted_l1": math.exp(icpt) * need ** (-p),
            "predicted_seconds": max(float(t0), 0.0) + float(t1) * need, "exponent": p}


def tune(rows: Sequence[dict[str, Any]], target: float, error_key: str = "l1") -> dict[str, Any]:
    """Choose the cheapest setting reaching ``target`` relative L1; returns a dict with a ``summary``."""
    warp_rows = [r for r in rows if r.get("kind", "warp") == "warp" and np.isfinite(r.get(error_key, np.nan))]
    ok = [r for r in warp_rows if r[error_key] <= target]
    table_choice = min(ok, key=lambda r: r["seconds"]) if ok else None
    models, solutions = [], []
    widths = [r["pano_size"][0] for r in warp_rows]
    spps = [r.get("spp", 1) for r in warp_rows]
    max_width = 2.0 * max(widths) if widths else 0.0
    for setting, rs in _group(warp_rows).items():
        m = fit_model(rs, error_key)
        if m is None:
            continue
        models.append(m)
        sol = solve(m, target, max_width, 4.0 * max(spps))
        if sol is not None:
            solutions.append(sol)
    model_choice = min(solutions, key=lambda s: s["predicted_seconds"]) if solutions else None
    lines = [f"target: relative L1 <= {100 * target:.3g}%"]
    if table_choice is not None:
        lines.append(
            f"measured table: {table_choice['label']} ({table_choice.get('spp', 1)} spp) reaches "
            f"{100 * table_choice[error_key]:.3f}% in {table_choice['seconds']:.3f} s "
            f"(render {table_choice['trace_seconds']:.3f} s + warp {table_choice['warp_seconds'] * 1e3:.1f} ms)")
    else:
        lines.append("measured table: no measured setting reaches the target")
    if model_choice is not None:
        lines.append(
            f"fitted model: {model_choice['setting']} from a {model_choice['pano_size'][0]}x"
            f"{model_choice['pano_size'][1]} panorama at {model_choice['spp']} spp is predicted to give "
            f"{100 * model_choice['predicted_l1']:.3f}% in {model_choice['predicted_seconds']:.3f} s")
    else:
        lines.append("fitted model: no setting is predicted to reach the target within 2x the measured sizes")
    choice = None
    if table_choice is not None and (model_choice is None
                                     or table_choice["seconds"] <= model_choice["predicted_seconds"]):
        choice = {"from": "table", "label": table_choice["label"], "setting": table_choice["setting"],
                  "pano_size": table_choice["pano_size"], "spp": table_choice.get("spp", 1),
                  "l1": table_choice[error_key], "seconds": table_choice["seconds"]}
        lines.append(f"chosen: {table_choice['label']} (measured)")
    elif model_choice is not None:
        choice = {"from": "model", **model_choice}
        lines.append(f"chosen: {model_choice['setting']} at {model_choice['pano_size'][0]}x"
                     f"{model_choice['pano_size'][1]}, {model_choice['spp']} spp (predicted; not yet measured)")
    else:
        lines.append("chosen: nothing; render the target directly or allow a larger error")
    direct = direct_alternative(rows, target, error_key)
    if direct is not None:
        lines.append(
            f"for comparison, one direct render of the target: {direct['spp']} spp predicted to give "
            f"{100 * direct['predicted_l1']:.3f}% in {direct['predicted_seconds']:.3f} s "
            f"(the panorama pays off once several views share it: see the amortised trade)")
    return {
        "direct": direct,
        "target": target,
        "choice": choice,
        "table_choice": None if table_choice is None else table_choice["label"],
        "models": [m.__dict__ for m in models],
        "solutions": solutions,
        "summary": "\n".join(lines),
    }
