#!/usr/bin/env python3
"""Build the speed table from benchmark JSON files (``lenslab bench TARGET --json FILE``).

    python tools/speed_table.py bench-results/*.json                     # print the table
    python tools/speed_table.py bench-results/*.json --readme PAGE.md    # replace it in a page

The documentation site's speed page (``docs/speed.md``) gets this table from ``bench-results/`` at
every build (``tools/mkdocs_hooks.py``); ``--readme`` replaces it in any page between
``<!-- speed-table:start -->`` and ``<!-- speed-table:end -->``. Each row is one figure: the
benchmark, what was measured, the figure, the aim, and whether it is met, so a missed aim is marked,
never hidden. The run's load average is given under the table.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

START, END = "<!-- speed-table:start -->", "<!-- speed-table:end -->"


def fmt(value: float | None, unit: str) -> str:
    if value is None:
        return "-"
    text = f"{value:.3g}" if abs(value) < 1000 else f"{value:.0f}"
    if unit in ("x", "%"):
        return text + unit
    return f"{text} {unit}".strip()


def aim_text(fig: dict) -> str:
    if fig.get("aim") is None:
        return "-"
    sign = "<=" if fig.get("better", "lower") == "lower" else ">="
    return f"{sign} {fmt(fig['aim'], fig.get('unit', ''))}"


def met_text(fig: dict) -> str:
    ok = fig.get("met")
    return "-" if ok is None else ("met" if ok else "**missed**")


def table(records: list[dict]) -> str:
    lines = ["| benchmark | figure | measured | aim | met |", "|---|---|---|---|---|"]
    loads = []
    for rec in records:
        name = f"`lenslab bench {rec['benchmark']}`" if rec.get("benchmark") != "tracer" else "`tracer bench`"
        for fig in rec.get("figures", []):
            if fig.get("detail"):
                continue
            label = fig["label"] + (f" ({fig['note']})" if fig.get("note") else "")
            lines.append(f"| {name} | {label} | {fmt(fig['value'], fig.get('unit', ''))} | {aim_text(fig)} "
                         f"| {met_text(fig)} |")
        if rec.get("load_start") and rec.get("load_end"):
            loads.append(f"{rec['benchmark']} {rec['load_start'][0]:.2f}-{rec['load_end'][0]:.2f}")
    cpus = {rec.get("machine", {}).get("cpus") for rec in records} - {None}
    foot = (f"\nMeasured on a {'/'.join(map(str, sorted(cpus)))}-core machine; one-minute load average at the "
            f"start and end of each run: {', '.join(loads)}." if loads else "")
    return "\n".join(lines) + foot + "\n"


def build_parser() -> argparse.ArgumentParser:
    from lenslab.jobs.arguments import ArgumentParser  # one-line errors, no abbreviated options

    parser = ArgumentParser(prog="python tools/speed_table.py", description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="JSON files written by 'lenslab bench TARGET --json FILE'")
    parser.add_argument("--readme", help="replace the table between the markers in this README")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        records = [json.loads(Path(f).read_text(encoding="utf-8")) for f in args.files]
    except (OSError, ValueError) as exc:
        print(f"speed_table: {exc}", file=sys.stderr)
        return 1
    text = table(records)
    if not args.readme:
        sys.stdout.write(text)
        return 0
    readme = Path(args.readme)
    body = readme.read_text(encoding="utf-8")
    if START not in body or END not in body:
        print(f"speed_table: {readme} has no {START} ... {END} markers", file=sys.stderr)
        return 1
    head, rest = body.split(START, 1)
    _, tail = rest.split(END, 1)
    tmp = readme.with_name(f".{readme.name}.tmp")
    tmp.write_text(head + START + "\n" + text + END + tail, encoding="utf-8")
    tmp.replace(readme)
    print(f"{readme}: speed table rebuilt from {len(records)} run(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
