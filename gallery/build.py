"""Build ``index.html``: a static page of cards, its images written next to it, every link relative.

``build_gallery(out_dir, *items, validate_report=None, hdri_dir=None)`` takes records from
:mod:`gallery.items` (which point at HDR files inside ``out_dir``), renders one card per record or group
of records, writes the page images under ``out_dir/img/``, a small stylesheet and ``index.html``, and saves
the records as ``gallery.json`` so that ``python -m gallery OUT`` can build the page again.
"""

from __future__ import annotations

import html
import inspect
import json
import re
import time
from importlib import resources
from pathlib import Path
from typing import Any, Callable, Iterable

from gallery.errors import GalleryError
from gallery.items import Display, FileList, LensView, Panorama, RunInfo, ToneSet, from_json, to_json

MANIFEST = "gallery.json"
IMG_DIR = "img"
STYLE = "style.css"


def esc(value: Any) -> str:
    return html.escape(str(value), quote=True)


def slug(text: str) -> str:
    """A file- and anchor-safe name: lower case letters, digits and dashes."""
    s = re.sub(r"[^a-z0-9]+", "-", str(text).lower()).strip("-")
    return s or "item"


def card_text(func: Callable) -> str:
    """The card's text, from the docstring of the function that renders it, as HTML paragraphs.

    Blank lines separate paragraphs; ```code``` spans become ``<code>``.
    """
    doc = inspect.getdoc(func) or ""
    paras = [" ".join(p.split()) for p in re.split(r"\n\s*\n", doc) if p.strip()]
    out = []
    for p in paras:
        p = esc(p)
        p = re.sub(r"``(.+?)``", r"<code>\1</code>", p)
        out.append(f"<p>{p}</p>")
    return "\n".join(out)


def fmt_seconds(s: float | None) -> str:
    if s is None:
        return "-"
    if s < 1e-3:
        return f"{s * 1e6:.0f} \u00b5s"
    if s < 1:
        return f"{s * 1e3:.0f} ms"
    if s < 120:
        return f"{s:.2f} s"
    return f"{s / 60:.1f} min"


def fmt_percent(x: float | None, digits: int = 2) -> str:
    return "-" if x is None else f"{100 * x:.{digits}f}%"


def fmt_bytes(n: int) -> str:
    for unit in ("B", "KB", "MB", "GB"):
        if n < 1024 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n} B"


class Page:
    """What a card draws with: the output folder, the display settings, image and figure writers."""

    def __init__(self, out_dir: Path, display: Display):
        self.out_dir = Path(out_dir)
        self.img_dir = self.out_dir / IMG_DIR
        self.display = display
        self._names: set[str] = set()
        self.repairs: list[str] = []  # what tone mapping repaired (NaN, inf, negative values) in this card

    # -- inputs ----------------------------------------------------------------------------
    def path(self, rel: str | Path) -> Path:
        p = Path(rel)
        return p if p.is_absolute() else self.out_dir / p

    def read(self, rel: str | Path):
        """The float32 image of an HDR (or any) file named by a record."""
        from lenslab.io import read

        path = self.path(rel)
        if not path.is_file():
            raise GalleryError(f"gallery image {path} does not exist; run the step that writes it, or rebuild")
        image, _ = read(path)
        return image

    def tone(self, image, curve: str | None = None, exposure: float | str | None = None):
        import warnings

        from gallery.display import tone
        from lenslab.tone import ToneWarning

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ToneWarning)
            out = tone(image, curve or self.display.curve, self.display.exposure if exposure is None else exposure)
        for w in caught:
            if issubclass(w.category, ToneWarning):
                self.repairs.append(str(w.message))
            else:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return out

    # -- outputs ---------------------------------------------------------------------------
    def _name(self, name: str, ext: str) -> str:
        base = slug(name)
        candidate, i = f"{base}.{ext}", 2
        while candidate in self._names:
            candidate, i = f"{base}-{i}.{ext}", i + 1
        self._names.add(candidate)
        return candidate

    def save_image(self, name: str, rgb, *, encoded: bool = False, ext: str = "jpg", quality: int = 90) -> "Img":
        """Write a display image under ``img/`` and return it for an ``<img>`` tag.

        ``rgb`` is display-linear in [0, 1], or already display-encoded with ``encoded=True``
        (colour maps).
        """
        import numpy as np

        from lenslab.io import write

        self.img_dir.mkdir(parents=True, exist_ok=True)
        fname = self._name(name, ext)
        rgb = np.ascontiguousarray(np.clip(rgb, 0.0, 1.0), dtype=np.float32)
        options: dict[str, Any] = {"raw": True} if encoded else {}
        if ext in ("jpg", "jpeg"):
            options["quality"] = quality
        write(self.img_dir / fname, rgb, overwrite=True, **options)
        return Img(f"{IMG_DIR}/{fname}", rgb.shape[1], rgb.shape[0])

    def save_figure(self, name: str, fig, dpi: int = 100) -> "Img":
        """Save a matplotlib figure as PNG under ``img/`` (and close it)."""
        import matplotlib.pyplot as plt

        from lenslab.io.atomic import atomic_write_path

        self.img_dir.mkdir(parents=True, exist_ok=True)
        fname = self._name(name, "png")
        w, h = fig.get_size_inches()
        with atomic_write_path(self.img_dir / fname, overwrite=True) as tmp:
            fig.savefig(tmp, dpi=dpi, format="png")
        plt.close(fig)
        return Img(f"{IMG_DIR}/{fname}", round(w * dpi), round(h * dpi))

    def new_image_path(self, name: str, ext: str = "png") -> tuple[Path, str]:
        """A fresh file name under ``img/`` for an image some other writer makes: (path, relative URL)."""
        self.img_dir.mkdir(parents=True, exist_ok=True)
        fname = self._name(name, ext)
        return self.img_dir / fname, f"{IMG_DIR}/{fname}"

    def written_image(self, rel: str) -> "Img":
        """The :class:`Img` of a file already written under ``img/`` (its size read back from the file)."""
        import cv2

        im = cv2.imread(str(self.out_dir / rel), cv2.IMREAD_UNCHANGED)
        if im is None:
            raise GalleryError(f"{self.out_dir / rel} is not an image a browser can show (PNG or JPG expected)")
        return Img(rel, im.shape[1], im.shape[0])

    def copy_image(self, name: str, src: Path) -> "Img":
        """Copy an existing PNG/JPG (a report's plot) under ``img/``."""
        import shutil

        import cv2

        from lenslab.io.atomic import atomic_write_path

        self.img_dir.mkdir(parents=True, exist_ok=True)
        ext = src.suffix.lower().lstrip(".") or "png"
        fname = self._name(name, ext)
        with atomic_write_path(self.img_dir / fname, overwrite=True) as tmp:
            shutil.copyfile(src, tmp)
        im = cv2.imread(str(self.img_dir / fname), cv2.IMREAD_UNCHANGED)
        if im is None:
            raise GalleryError(f"{src} is not an image a browser can show (PNG or JPG expected)")
        return Img(f"{IMG_DIR}/{fname}", im.shape[1], im.shape[0])


class Img:
    """An image written for the page: its relative URL and pixel size."""

    def __init__(self, src: str, width: int, height: int):
        self.src, self.width, self.height = src, int(width), int(height)

    def tag(self, alt: str, cls: str = "") -> str:
        c = f' class="{esc(cls)}"' if cls else ""
        return (f'<img src="{esc(self.src)}" width="{self.width}" height="{self.height}" alt="{esc(alt)}"{c}>')

    def figure(self, caption: str, alt: str | None = None, cls: str = "", extra: str = "") -> str:
        """``<figure>`` with the image (linked to itself) and a caption; ``caption`` and ``extra`` are HTML."""
        c = f' class="{esc(cls)}"' if cls else ""
        alt_text = alt if alt is not None else re.sub(r"<[^>]+>", " ", caption)
        return (f'<figure{c}><a href="{esc(self.src)}">{self.tag(" ".join(html.unescape(alt_text).split()))}</a>'
                f"<figcaption>{caption}{extra}</figcaption></figure>")


def facts_table(rows: Iterable[tuple[str, Any]]) -> str:
    """A two-column table of (label, value) rows; values are escaped, None rows dropped."""
    body = "".join(f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in rows if v is not None)
    return f'<table class="facts">{body}</table>'


def section(card_id: str, title: str, func: Callable, body: str, cls: str = "") -> str:
    """One card: a heading, the card's text (its function's docstring) and its figures."""
    return (f'<section class="card {esc(cls)}" id="{esc(card_id)}">\n<h2>{esc(title)}</h2>\n'
            f'<div class="text">{card_text(func)}</div>\n{body}\n</section>')


# -- manifest ------------------------------------------------------------------------------
def save_manifest(out_dir: Path, items: list, validate_report, hdri_dir, title: str | None = None) -> Path:
    from lenslab.io.atomic import atomic_write_path

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
    from lenslab.io.atomic import atomic_write_path

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
    from lenslab.io.atomic import atomic_write_path

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
