"""List every lens model with its parameters, ranges and defaults.

Without arguments: one block per model (its equation's first line, then each parameter with its
default, range and meaning). With model names: the full description of those models.
A lens is named on the command line and in config files by a spec, ``name:key=value,...``, e.g.
``fisheye:fov=180,mapping=equisolid``, ``swirl:amount=6,base=fisheye,fov=180``,
``pincushion:k1=0.3,k2=0.05,fov=90`` or ``tiled:2x2,tiles=cams.toml``.
"""

from __future__ import annotations

import argparse
import inspect
import json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("models", nargs="*", metavar="MODEL",
                        help="show the full description of these models (default: list every model)")
    parser.add_argument("--json", action="store_true",
                        help="print the models and parameters as JSON (for scripts)")


def _default_text(value) -> str:
    from lenslab.lenses.base import format_number

    if isinstance(value, float):
        return format_number(value)
    if isinstance(value, str):
        return repr(value) if value == "" else value
    return str(value)


def _describe(cls) -> dict:
    doc = inspect.getdoc(cls) or ""
    params = [
        {"name": p.name, "default": p.default, "range": p.describe_range(), "doc": p.doc}
        for p in cls.params
    ]
    out = {"name": cls.name, "summary": doc.splitlines()[0] if doc else cls.summary, "params": params}
    from lenslab.lenses.wrapped import Wrapped

    if issubclass(cls, Wrapped):
        out["note"] = "takes the parameters of its base model too (e.g. fov for perspective)"
    return out


def run(args: argparse.Namespace) -> int:
    from lenslab.lenses import REGISTRY
    from lenslab.lenses.registry import lens_class

    names = [n.strip().lower() for n in args.models] or sorted(REGISTRY)
    classes = [lens_class(n) for n in names]  # unknown names raise, listing the valid ones
    if args.json:
        print(json.dumps([_describe(c) for c in classes], indent=2, default=str))
        return 0
    for i, cls in enumerate(classes):
        info = _describe(cls)
        if i:
            print()
        print(f"{info['name']}: {info['summary']}")
        if args.models:
            body = (inspect.getdoc(cls) or "").splitlines()[1:]
            for line in body:
                print(f"    {line}".rstrip())
        width = max((len(p["name"]) for p in info["params"]), default=0)
        for p in info["params"]:
            print(f"  {p['name']:<{width}}  default {_default_text(p['default']):<12} {p['range']:<28} {p['doc']}")
        if "note" in info:
            print(f"  ({info['note']})")
    if not args.models:
        print("\nSpec syntax: name:key=value,...  e.g. fisheye:fov=180,mapping=equisolid; "
              "'lenslab lenses MODEL' shows the equations.")
    return 0
