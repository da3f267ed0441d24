"""Write a validation to a report directory: ``results.json``, ``report.md`` and PNG plots.

- ``results.json``: the run's settings and every row (time and errors), and the Pareto front;
- ``report.md``: the same as tables a person reads, with the plots linked;
- ``error_vs_time.png``: relative L1 against seconds for every row, the Pareto front drawn through;
- ``error_maps.png``: the per-pixel relative error of the best and the worst setting;
- ``side_by_side.png``: reference | warped (best setting) | difference, tone-mapped alike.

Every file goes through :func:`lenslab.atomic.atomic_write_path`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from lenslab.atomic import atomic_write_path


def _json_default(o):
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.bool_,)):
        return bool(o)
    raise TypeError(f"cannot store {type(o).__name__} in JSON")


def _clean(obj):
    """NaN/inf are not JSON: store them as null (inf as the string 'inf')."""
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        if math.isnan(f):
            return None
        if math.isinf(f):
            return "inf" if f > 0 else "-inf"
        return f
    return obj


def write_json(path: Path, data: dict[str, Any]) -> None:
    with atomic_write_path(path) as tmp:
        tmp.write_text(json.dumps(_clean(data), indent=2, default=_json_default) + "\n")


def write_text(path: Path, text: str) -> None:
    with atomic_write_path(path) as tmp:
        tmp.write_text(text)


def _pct(v) -> str:
    return "-" if v is None or not np.isfinite(v) else f"{100 * v:.3f}%"


def _sec(v) -> str:
    return "-" if v is None or not np.isfinite(v) else (f"{v * 1e3:.1f} ms" if v < 1 else f"{v:.2f} s")


def _num(v, fmt="{:.2f}") -> str:
    return "-" if v is None or not np.isfinite(v) else fmt.format(v)


def rows_table(rows: Sequence[dict[str, Any]], front: Sequence[str] = ()) -> str:
    head = ("| setting | trace | warp | total | rel. L1 | L1 interior | L1 edges | excess L1 | PSNR log | "
            ">5% off | FLIP | Pareto |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    lines = []
    for r in rows:
        lines.append(
            f"| {r['label']} | {_sec(r['trace_seconds'])} | {_sec(r['warp_seconds'])} | {_sec(r['seconds'])} | "
            f"{_pct(r['l1'])} | {_pct(r.get('l1_interior'))} | {_pct(r.get('l1_edge'))} | "
            f"{_pct(r.get('excess_l1'))} | {_num(r.get('psnr_log'))} dB | {_pct(r.get('off5'))} | "
            f"{_num(r.get('flip'), '{:.4f}')} | {'yes' if r['label'] in front else ''} |")
    return head + "\n".join(lines) + "\n"


def markdown(val, extra_sections: Sequence[str] = ()) -> str:
    from lenslab.validate.run import pareto_front

    m = val.meta
    front = pareto_front(val.rows)
    ref = m["reference"]
    lines = [
        f"# Validation: {m['source']} -> `{m['target']}` at {m['size'][0]}x{m['size'][1]}",
        "",
        f"- mode: **{m['mode']}**; panoramas rendered with {m['panorama_spp']} sample(s) per pixel",
        f"- reference: direct render through the target camera, {ref['spp']} samples per pixel, "
        f"{_sec(ref['seconds'])}; its own noise alone would read as {_pct(ref.get('noise_l1'))} relative L1",
        f"- edges: {m['edges']} ({_pct(m['edge_share'])} of the valid pixels)",
        f"- metrics: {m['metric_notes']}",
        "",
        "## Every setting",
        "",
        rows_table(val.rows, front),
        "## Pareto front (fastest for its error)",
        "",
        ", ".join(front) or "-",
        "",
        "![error against time](error_vs_time.png)",
        "",
        "![error maps of the best and worst setting](error_maps.png)",
        "",
        "![reference, warped and difference](side_by_side.png)",
        "",
    ]
    lines.extend(extra_sections)
    return "\n".join(lines) + "\n"


def _best_worst(val):
    rows = [r for r in val.rows if r["label"] in val.images and np.isfinite(r["l1"]) and r["kind"] == "warp"]
    if not rows:
        return None, None
    best = min(rows, key=lambda r: r["l1"])
    worst = max(rows, key=lambda r: r["l1"])
    return best, worst


def _display(image):
    from lenslab.metrics import to_display as disp

    return disp(image, "hable", 0.0)


def plot_error_vs_time(val, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lenslab.validate.run import pareto_front

    fig, ax = plt.subplots(figsize=(7.5, 5))
    groups: dict[str, list] = {}
    for r in val.rows:
        key = "direct render" if r["kind"] == "direct" else r["setting"]
        groups.setdefault(key, []).append(r)
    markers = "osD^v<>pPX*h"
    for i, (key, rs) in enumerate(sorted(groups.items())):
        rs = sorted(rs, key=lambda r: r["seconds"])
        ax.plot([r["seconds"] for r in rs], [100 * r["l1"] for r in rs], marker=markers[i % len(markers)],
                linestyle="-" if key != "direct render" else "--", label=key, alpha=0.85)
        for r in rs:
            if r.get("pano_size"):
                ax.annotate(f"{r['pano_size'][0]}", (r["seconds"], 100 * r["l1"]), fontsize=7,
                            xytext=(3, 3), textcoords="offset points")
    front = set(pareto_front(val.rows))
    fr = sorted([r for r in val.rows if r["label"] in front], key=lambda r: r["seconds"])
    if fr:
        ax.step([r["seconds"] for r in fr], [100 * r["l1"] for r in fr], where="post", color="k",
                linewidth=2.0, alpha=0.35, label="Pareto front")
    noise = val.meta["reference"].get("noise_l1")
    if noise and np.isfinite(noise) and noise > 0:
        ax.axhline(100 * noise, color="grey", linestyle=":", label="reference noise floor")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds (panorama render + warp, or direct render)")
    ax.set_ylabel("relative L1 vs reference (%)")
    ax.set_title(f"{val.meta['target']} {val.meta['size'][0]}x{val.meta['size'][1]}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    with atomic_write_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def plot_error_maps(val, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lenslab.metrics import error_map, valid_mask

    best, worst = _best_worst(val)
    if best is None:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.8))
    vmax = None
    maps = []
    for r in (best, worst):
        img, alpha = val.images[r["label"]]
        maps.append(error_map(val.reference.image, img, valid_mask(val.reference.alpha, alpha)))
    finite = np.concatenate([m[np.isfinite(m)] for m in maps]) if maps else np.zeros(1)
    vmax = float(np.percentile(finite, 99.5)) if finite.size else 1.0
    vmax = max(vmax, 1e-4)
    for ax, r, m in zip(axes, (best, worst), maps):
        im = ax.imshow(100 * m, cmap="magma", vmin=0, vmax=100 * vmax)
        ax.set_title(f"{'best' if r is best else 'worst'}: {r['label']}\nrel. L1 {100 * r['l1']:.3f}%",
                     fontsize=9)
        ax.axis("off")
    fig.colorbar(im, ax=axes, shrink=0.8, label="per-pixel relative error (%)")
    with atomic_write_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def plot_side_by_side(val, path: Path, label: str | None = None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lenslab.metrics import valid_mask

    best, _ = _best_worst(val)
    if best is None:
        return
    label = label or best["label"]
    img, alpha = val.images[label]
    ref = val.reference.image
    m = valid_mask(val.reference.alpha, alpha)
    diff = np.where(m, np.abs(img - ref).sum(-1), 0.0)
    scale = float(np.percentile(diff[m], 99.5)) if m.any() else 1.0
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.6))
    axes[0].imshow(_display(ref))
    axes[0].set_title(f"reference ({val.meta['reference']['spp']} spp)", fontsize=9)
    axes[1].imshow(_display(img))
    axes[1].set_title(f"warped: {label}", fontsize=9)
    im = axes[2].imshow(diff, cmap="inferno", vmin=0, vmax=max(scale, 1e-6))
    axes[2].set_title("|warped - reference| (sum over RGB)", fontsize=9)
    for ax in axes:
        ax.axis("off")
    fig.colorbar(im, ax=axes[2], shrink=0.8)
    with atomic_write_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def write_report(val, out_dir, extra: dict[str, Any] | None = None, extra_sections: Sequence[str] = ()) -> Path:
    """Write ``results.json``, ``report.md`` and the plots into ``out_dir`` (created if missing)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    data = val.to_json()
    if extra:
        data.update(extra)
    write_json(out / "results.json", data)
    plot_error_vs_time(val, out / "error_vs_time.png")
    plot_error_maps(val, out / "error_maps.png")
    plot_side_by_side(val, out / "side_by_side.png")
    write_text(out / "report.md", markdown(val, extra_sections))
    return out
