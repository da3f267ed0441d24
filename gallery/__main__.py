"""Build (or rebuild) a gallery page: ``python -m gallery OUT [--hdri DIR] [--report DIR] [--check]``.

OUT is a folder: one made by ``lenslab demo`` keeps the records of its renders in ``gallery.json`` and
its page is rebuilt from them (adding the cards asked for); an empty or new folder gets a page with
the cards asked for alone.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lenslab.jobs.arguments import ArgumentParser
from lenslab.errors import UsageError
from lenslab.jobs.funnel import run_command


def build_parser() -> argparse.ArgumentParser:
    p = ArgumentParser(prog="python -m gallery", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out", type=Path, help="gallery folder (index.html is written there)")
    p.add_argument("--hdri", type=Path, metavar="DIR",
                   help="folder of equirect HDR panoramas (.exr/.pfm) to warp into a couple of lenses")
    p.add_argument("--report", type=Path, metavar="DIR",
                   help="a 'lenslab validate' report folder, shown as the speed/accuracy card")
    p.add_argument("--title", help="page title (default: the one stored with the page, else 'lenslab gallery')")
    p.add_argument("--check", action="store_true",
                   help="open the page in headless Chromium, check that every image loads and save "
                        "screenshot.png next to it; an existing page is checked as it is, not rebuilt "
                        "(unless --overwrite or an option that changes it is given)")
    p.add_argument("--readme-images", type=Path, metavar="DIR",
                   help="also write small JPG montages of the page (each under 60 KB) into DIR, for a README")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the page (index.html, its images and the README montages) when it exists")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--debug", action="store_true", help="on an error, print the full traceback too")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)  # a usage error: one line on stderr and SystemExit(2)
    return run_command("python -m gallery", lambda: run(args), debug=args.debug)


def run(args) -> int:
    from gallery.build import build_gallery, load_manifest
    from lenslab.jobs.policy import check_output, check_output_dir

    stored = load_manifest(args.out)
    report = args.report or stored.get("validate_report")
    hdri = args.hdri or stored.get("hdri_dir")
    if not stored["items"] and report is None and hdri is None:
        raise UsageError(f"{args.out} holds no gallery records (gallery.json); run 'lenslab demo -o DIR' "
                         "first, or give --hdri DIR or --report DIR")
    for folder in (report, hdri):
        if folder is not None and Path(folder).resolve() == Path(args.out).resolve():
            raise UsageError(f"{folder} is an input of the page; it is never written into, even with "
                              "--overwrite: give another output folder")
    check_output_dir(args.out)
    index = Path(args.out) / "index.html"
    changes = args.overwrite or any(v is not None for v in (args.hdri, args.report, args.title, args.readme_images))
    if args.check and index.is_file() and not changes:  # a check reads the page; it needs no --overwrite
        return _check(args, index)
    check_output(index, overwrite=args.overwrite)
    if args.readme_images is not None:
        from gallery.montage import MONTAGES

        check_output_dir(args.readme_images)
        for name in MONTAGES:
            check_output(Path(args.readme_images) / name, overwrite=args.overwrite)
    index = build_gallery(args.out, *stored["items"], validate_report=report, hdri_dir=hdri,
                          title=args.title or stored.get("title"), progress=not args.quiet)
    print(f"gallery: {index}")
    if args.readme_images is not None:
        from gallery.montage import readme_images

        for path in readme_images(args.out, args.readme_images):
            print(f"  {path} ({path.stat().st_size / 1000:.0f} KB)")
    return _check(args, index) if args.check else 0


def _check(args, index) -> int:
    """Open the page in headless Chromium; the screenshot replaces an older one only with --overwrite."""
    from gallery.browser import check_page

    shot = Path(args.out) / "screenshot.png"
    keep = shot.exists() and not args.overwrite
    problems = check_page(index, None if keep else shot)
    for p in problems:
        print(f"  {p}", file=sys.stderr)
    saved = f"{shot} exists and is kept (--overwrite replaces it)" if keep else f"screenshot {shot}"
    print(f"checked in Chromium: {'all images loaded' if not problems else f'{len(problems)} problem(s)'}; {saved}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
