"""What every card is made of: the page's image writer (:class:`Page`), image tags, tables, sections
and the formatting of numbers. The cards and the page builder both import from here.
"""

from __future__ import annotations

import html
import inspect
import re
from pathlib import Path
from typing import Any, Callable, Iterable

from gallery.errors import GalleryError
from gallery.items import Display

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

        from lenslab.atomic import atomic_write_path

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
