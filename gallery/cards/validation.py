"""The validation card: the speed/accuracy trade measured by ``lenslab validate``."""

from __future__ import annotations

import json
from pathlib import Path

from gallery.page import Page, esc, fmt_percent, fmt_seconds, section
from gallery.errors import GalleryError

RESULTS = "results.json"


def report_results(report_dir: Path) -> list[tuple[Path, dict]]:
    """Every ``results.json`` of a report folder (at its top, or one per sub-folder for several targets)."""
    paths = [report_dir / RESULTS] if (report_dir / RESULTS).is_file() else sorted(report_dir.glob(f"*/{RESULTS}"))
    if not paths:
        raise GalleryError(f"{report_dir} holds no {RESULTS}; give the -o folder of 'lenslab validate'")
    out = []
    for p in paths:
        try:
            data = json.loads(p.read_text(encoding="utf-8"))
            rows = data["rows"]
        except (ValueError, KeyError, TypeError) as exc:
            raise GalleryError(f"{p} is not a validation result ({exc}); run 'lenslab validate' again") from None
        if not isinstance(rows, list):
            raise GalleryError(f"{p}: 'rows' is not a list; run 'lenslab validate' again")
        out.append((p, data))
    return out


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and x == x and abs(x) != float("inf")


def plot_trade(data: dict, title: str):
    """Relative L1 error against time (log-log), one marker per setting, the Pareto front as a line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in data["rows"] if _finite(r.get("seconds")) and _finite(r.get("l1")) and r["seconds"] > 0
            and r["l1"] > 0]
    fig, ax = plt.subplots(figsize=(8.4, 4.4), layout="constrained")
    groups: dict[str, list[dict]] = {}
    for r in rows:
        key = "direct trace" if r.get("kind") == "direct" else (
            f"panorama {r['pano_size'][0]}x{r['pano_size'][1]}" if r.get("pano_size") else "warp")
        groups.setdefault(key, []).append(r)
    markers = "osD^v<>p*h"
    for i, (key, rs) in enumerate(groups.items()):
        ax.scatter([r["seconds"] for r in rs], [100 * r["l1"] for r in rs], label=key,
                   marker="x" if key == "direct trace" else markers[i % len(markers)], s=36, zorder=3)
    front = set(data.get("pareto") or [])
    fr = sorted((r for r in rows if r.get("label") in front), key=lambda r: r["seconds"])
    if fr:
        ax.step([r["seconds"] for r in fr], [100 * r["l1"] for r in fr], where="post", color="0.5", lw=1,
                label="Pareto front", zorder=2)
    noise = (data.get("meta") or {}).get("reference", {}).get("noise_l1")
    if _finite(noise) and noise > 0:
        ax.axhline(100 * noise, color="tab:red", ls="--", lw=1, label="reference noise floor")
    from matplotlib.ticker import FuncFormatter, LogLocator

    ax.set_xscale("log")
    ax.set_yscale("log")
    def label(unit: str, minor_leads: str):
        def fmt(v, _):  # minor ticks labelled at the given leading digits, so short ranges still get numbers
            return f"{v:g}{unit}" if f"{v:.0e}"[0] in minor_leads else ""
        return FuncFormatter(fmt)

    for axis, unit, leads in ((ax.xaxis, " s", "125"), (ax.yaxis, "%", "12345678")):
        axis.set_major_locator(LogLocator(base=10))
        axis.set_minor_locator(LogLocator(base=10, subs=tuple(range(2, 10))))
        axis.set_major_formatter(label(unit, "123456789"))
        axis.set_minor_formatter(label(unit, leads))
    ax.set_xlabel("seconds (panorama trace + warp, or direct trace)")
    ax.set_ylabel("relative L1 error vs reference")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    if rows:
        ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return fig


def validation(page: Page, report_dir: Path) -> str:
    """How much accuracy each second buys. ``lenslab validate`` traced a reference view directly with
    many samples, traced panoramas at several sizes from the same eye, warped each into the view with
    each filter, and compared every result with the reference; direct traces at low sample counts are
    the alternative the panorama route competes with.

    Points further down cost less error, points further left less time; the Pareto front links the
    settings nothing else beats on both. The dashed line is the reference's own Monte Carlo noise:
    errors near it are the reference's, not the warp's. A panorama is traced once for any number of
    views, so for many views its cost is shared while each direct trace is paid again."""
    parts = []
    for path, data in report_results(report_dir):
        meta = data.get("meta") or {}
        target = meta.get("target", path.parent.name)
        size = meta.get("size")
        title = f"{target}" + (f" at {size[0]}x{size[1]}" if size else "") + f" ({meta.get('mode', '')})"
        img = page.save_figure(f"validation-{path.parent.name}", plot_trade(data, title))
        front = set(data.get("pareto") or [])
        body_rows = []
        for r in sorted(data["rows"], key=lambda r: (r.get("seconds") or 0)):
            if r.get("label") not in front:
                continue
            body_rows.append(
                f"<tr><td>{esc(r.get('label', ''))}</td><td class=num>{esc(fmt_seconds(r.get('seconds')))}</td>"
                f"<td class=num>{esc(fmt_percent(r.get('l1')))}</td>"
                f"<td class=num>{esc(fmt_percent(r.get('l1_interior')))}</td>"
                f"<td class=num>{esc(fmt_percent(r.get('noise_l1')))}</td></tr>")
        table = ('<table class="results"><thead><tr><th>setting on the Pareto front</th><th>time</th>'
                 "<th>relative L1</th><th>away from edges</th><th>reference noise</th></tr></thead>"
                 f"<tbody>{''.join(body_rows)}</tbody></table>") if body_rows else ""
        parts.append(f'<div class="figures">{img.figure(esc(title))}</div>{table}')
    body = "".join(parts) + f'<p class="note">from {esc(report_dir)}</p>'
    return section("validation", "Speed against accuracy", validation, body, cls="wide")
