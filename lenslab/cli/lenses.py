"""List every lens model with its parameters, ranges and defaults.

Without arguments: one block per model (its equation's first line, then each parameter with its
default, range and meaning). With model names: the full description of those models.
A lens is named on the command line and in config files by a spec, ``name:key=value,...``, e.g.
``fisheye:fov=180,mapping=equisolid``, ``swirl:amount=6,base=fisheye,fov=180``,
``pincushion:k1=0.3,k2=0.05,fov=90`` or ``tiled:2x2,tiles=cams.toml``.
Real lenses: ``--lensfun "samyang 8mm"`` searches the lensfun database and shows each profile; use one
as ``lensfun:lens=NAME,camera=NAME,focal=8,aperture=5.6`` (quote a name holding a comma: lens="...").
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
    from lenslab.jobs.arguments import non_empty

    parser.add_argument("--lensfun", metavar="QUERY", type=non_empty,
                        help='find real lenses and cameras in the lensfun database, e.g. "samyang 8mm", and show '
                             "what each profile holds (needs lenslab[lensfun])")
    parser.add_argument("--lensfun-db", metavar="DIR", action="append", default=[],
                        help="also read your own lensfun XML files from DIR (a directory or one file; repeatable)")
    parser.add_argument("--lensfun-db-only", action="store_true",
                        help="read only the --lensfun-db files, not the database bundled with lensfunpy")


def _default_text(value) -> str:
    from lenslab.lenses.core.base import format_number

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
    from lenslab.lenses import REGISTRY

    entry = REGISTRY.entry(cls.name)
    if entry.aliases:
        out["aliases"] = list(entry.aliases)
    if entry.references:
        out["references"] = list(entry.references)
    from lenslab.lenses.core.wrapped import Wrapped

    if issubclass(cls, Wrapped):
        out["note"] = "takes the parameters of its base model too (e.g. fov for perspective)"
    return out


def run_lensfun(args: argparse.Namespace) -> int:
    from lenslab.errors import LensError
    from lenslab.lenses.lensfun import database as lensfun_db

    import contextlib

    if args.lensfun is None:
        return 0
    own = args.lensfun_db or args.lensfun_db_only  # your files for this search only
    with (lensfun_db.using_database(args.lensfun_db, bundled=not args.lensfun_db_only) if own
          else contextlib.nullcontext()):
        from lenslab.lenses.lensfun.match import search

        lenses, cameras = search(args.lensfun)
        if not lenses and not cameras:
            raise LensError(f"lensfun: no lens or camera matches {args.lensfun!r}")
        for i, lens in enumerate(lenses):
            print(("\n" if i else "") + "\n".join(lensfun_db.describe_lens(lens)))
        if cameras:
            print(("\n" if lenses else "") + ("Cameras named so that these lenses fit (camera=NAME sets the crop "
                                               "factor and the mount):" if lenses else
                                               "Cameras (camera=NAME sets the crop factor and the mount):"))
            for cam in cameras:
                print("  " + lensfun_db.describe_camera(cam))
    return 0


#: what ``lenslab lenses`` says of a photo's own lens (``exif`` names no model of its own)
PHOTO_LENS = ("A photo's own lens: --from exif (the pinhole of its EXIF 35 mm equivalent focal length; "
              "exif:photo=PHOTO elsewhere), --from lensfun:auto (the lensfun profile its metadata names).")
EXIF_FORMULA = ("perspective:fov=FOV, tan(FOV/2) = 21.63 mm / f35 * W / hypot(W, H) for the W x H photo as shown (the "
                "36 x 24 mm frame's diagonal, 43.27 mm, seeing what the photo's does); 'lenslab info PHOTO' prints it")


def run(args: argparse.Namespace) -> int:
    if args.lensfun is not None or args.lensfun_db or args.lensfun_db_only:
        if args.lensfun is None:
            from lenslab.errors import UsageError

            raise UsageError("--lensfun-db and --lensfun-db-only go with --lensfun QUERY")
        return run_lensfun(args)
    from lenslab.lenses import REGISTRY
    from lenslab.lenses.registry import lens_class

    names = [n.strip().lower() for n in args.models] or sorted(REGISTRY)
    if len(names) == 1 and names[0] in ("exif", "lensfun:auto", "auto"):  # no model: specs of a photo's own lens
        print(f"{names[0]}: {PHOTO_LENS}" + (f"\n  {EXIF_FORMULA}" if names[0] == "exif" else ""))
        return 0
    classes = [lens_class(n) for n in names]  # unknown names raise, listing the valid ones
    if args.json:
        print(json.dumps([_describe(c) for c in classes], indent=2, default=str))
        return 0
    for i, cls in enumerate(classes):
        info = _describe(cls)
        if i:
            print()
        print(f"{info['name']}: {info['summary']}")
        if info.get("aliases"):
            print(f"  (also read as {', '.join(info['aliases'])})")
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
        print(PHOTO_LENS)
    return 0
