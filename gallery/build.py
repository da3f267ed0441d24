"""Build ``index.html``: a static page of cards, its images written next to it, every link relative.

``build_gallery(out_dir, *items, validate_report=None, hdri_dir=None)`` takes records from
:mod:`gallery.items` (which point at HDR files inside ``out_dir``), renders one card per record or group
of records, writes the page images under ``out_dir/img/``, a small stylesheet and ``index.html``, and saves
the records as ``gallery.json`` so that ``python -m gallery OUT`` can build the page again.
"""

from __future__ import annotations

import json
import re
import time
from importlib import resources
from pathlib import Path
from typing import Any, Callable

from gallery.errors import GalleryError
from gallery.items import Display, FileList, LensView, Panorama, RunInfo, ToneSet, from_json, to_json
from gallery.page import STYLE, Page, esc, fmt_seconds

MANIFEST = "gallery.json"


def save_manifest(out_dir: Path, items: list, validate_report, hdri_dir, title: str | None = None) -> Path:
    from lenslab.atomic import atomic_write_path

    data = {
        "generator": "lenslab gallery",
        "title": title,
        "items": [to_json(i) for i in items],
        "validate_report": str(Path(validate_report).resolve()) if validate_report else None,
        "hdri_dir": str(Path(hdri_dir).resolve()) if hdri_dir else None,
    }
    path = Path(out_dir) / MANIFEST
    with atomic_write_path(path, overwrite=True) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    return path


def load_manifest(out_dir: Path) -> dict[str, Any]:
    """The records of an earlier build (``gallery.json``); empty when there is none."""
    path = Path(out_dir) / MANIFEST
    if not path.is_file():
        return {"items": [], "validate_report": None, "hdri_dir": None, "title": None}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        data["items"] = [from_json(d) for d in data.get("items", [])]
    except (ValueError, TypeError, KeyError) as exc:
        raise GalleryError(f"{path} is not a gallery record file ({exc}); delete it to start a fresh page") from None
    return data


# -- the page ------------------------------------------------------------------------------
def build_gallery(out_dir, *items, validate_report=None, hdri_dir=None, title: str | None = None,
                  progress: bool = False) -> Path:
    """Render the cards for ``items`` (records from :mod:`gallery.items`) into ``out_dir/index.html``.

    ``validate_report``: a ``lenslab validate`` report directory, shown as the speed/accuracy card.
    ``hdri_dir``: a folder of equirect HDR panoramas (EXR), each warped into a couple of lenses.
    Returns the path of ``index.html``.
    """
    from gallery import cards
    from lenslab.atomic import atomic_write_path

    t0 = time.perf_counter()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if len(items) == 1 and isinstance(items[0], (list, tuple)):
        items = tuple(items[0])
    display = next((i for i in items if isinstance(i, Display)), Display())
    page = Page(out_dir, display)
    if validate_report is not None and not Path(validate_report).is_dir():
        raise GalleryError(f"validation report {validate_report} is not a directory; "
                           "give the -o folder of 'lenslab validate'")
    if hdri_dir is not None and not Path(hdri_dir).is_dir():
        raise GalleryError(f"HDRI folder {hdri_dir} is not a directory; give a folder of equirect .exr panoramas")

    panoramas = [i for i in items if isinstance(i, Panorama)]
    views = [i for i in items if isinstance(i, LensView)]
    tones = [i for i in items if isinstance(i, ToneSet)]
    files = [i for i in items if isinstance(i, FileList)]
    runs = [i for i in items if isinstance(i, RunInfo)]
    compared = [v for v in views if v.direct]

    jobs: list[tuple[str, Callable[[], str]]] = []
    for p in panoramas:
        jobs.append(("panorama", lambda p=p: cards.panorama(page, p)))
    if compared:
        jobs.append(("comparisons", lambda: cards.lens_comparisons(page, compared)))
    if views:
        jobs.append(("lens views", lambda: cards.lens_views(page, views)))
    for t in tones:
        jobs.append(("tone curves", lambda t=t: cards.tone_strip(page, t)))
    if tones or panoramas or views:
        jobs.append(("curve plot", lambda: cards.tone_curves(page, tones[0] if tones else None)))
    if validate_report is not None:
        jobs.append(("validation", lambda: cards.validation(page, Path(validate_report))))
    if hdri_dir is not None:
        jobs.append(("hdri", lambda: cards.hdri(page, Path(hdri_dir))))
    for f in files:
        jobs.append(("files", lambda f=f: cards.files(page, f)))

    import sys

    from tqdm import tqdm

    sections = []
    bar = tqdm(jobs, desc="gallery", unit="card", disable=not (progress and sys.stderr.isatty()), leave=False)
    for _, job in bar:
        page.repairs.clear()
        card = job()
        if page.repairs:  # never hidden: say on the card what tone mapping had to repair
            unique = list(dict.fromkeys(page.repairs))
            more = f" (and {len(unique) - 3} more)" if len(unique) > 3 else ""
            note = f'<p class="note">for display, {esc("; ".join(unique[:3]))}{more}</p>'
            card = card[: card.rfind("</section>")] + note + "\n</section>"
        sections.append(card)

    save_manifest(out_dir, list(items), validate_report, hdri_dir, title)
    _write_style(out_dir)
    index = out_dir / "index.html"
    page_html = render_page(title or "lenslab gallery", sections, runs[0] if runs else None,
                            time.perf_counter() - t0)
    with atomic_write_path(index, overwrite=True) as tmp:
        Path(tmp).write_text(page_html, encoding="utf-8")
    return index


def _write_style(out_dir: Path) -> None:
    from lenslab.atomic import atomic_write_path

    css = resources.files("gallery").joinpath(STYLE).read_text(encoding="utf-8")
    with atomic_write_path(out_dir / STYLE, overwrite=True) as tmp:
        Path(tmp).write_text(css, encoding="utf-8")


def render_page(title: str, sections: list[str], run: RunInfo | None, build_seconds: float) -> str:
    from lenslab import __version__

    heads = re.findall(r'<section class="card[^"]*" id="([^"]+)">\n<h2>(.*?)</h2>', "\n".join(sections))
    nav = "".join(f'<a href="#{i}">{t}</a>' for i, t in heads)
    foot = [f"lenslab {esc(__version__)}"]
    if run is not None:
        if run.command:
            foot.append(f"made by <code>{esc(run.command)}</code>")
        if run.seconds:
            foot.append(f"in {esc(fmt_seconds(run.seconds))}")
        if run.settings:
            foot.append("; ".join(f"{esc(k)} {esc(v)}" for k, v in run.settings.items()))
    foot.append(f"page built in {esc(fmt_seconds(build_seconds))}")
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{esc(title)}</title>
<link rel="stylesheet" href="{STYLE}">
</head>
<body>
<header>
<h1>{esc(title)}</h1>
<nav>{nav}</nav>
</header>
<main>
{chr(10).join(sections)}
</main>
<footer>{" &middot; ".join(foot)}</footer>
</body>
</html>
"""
