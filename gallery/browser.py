"""Open a gallery page in headless Chromium: check that every image loaded, and take a screenshot.

No browser-driver package is needed: Chromium's own ``--dump-dom`` and ``--screenshot`` switches do
the work. To read the images' state, a copy of the page with a tiny script is opened; the script
writes each image's ``naturalWidth`` into the DOM once the page has loaded, and ``--dump-dom`` prints
that DOM. The copy sits next to ``index.html`` (so relative links resolve) and is removed afterwards.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from gallery.errors import GalleryError

CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable", "chrome")
RESULT_ID = "lenslab-image-check"

# The switches keep a headless run quiet, offline and reproducible (no sandbox: it runs as root in CI).
FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--disable-extensions", "--hide-scrollbars", "--mute-audio", "--no-default-browser-check",
)

CHECK_SCRIPT = """<script>
(function () {
  function report() {
    var out = Array.prototype.map.call(document.images, function (im) {
      return {src: im.getAttribute("src"), naturalWidth: im.naturalWidth, naturalHeight: im.naturalHeight,
              complete: im.complete};
    });
    var pre = document.createElement("pre");
    pre.id = "%s";
    pre.textContent = JSON.stringify(out);
    document.body.appendChild(pre);
  }
  if (document.readyState === "complete") { report(); } else { window.addEventListener("load", report); }
})();
</script>""" % RESULT_ID


def find_chromium() -> str:
    """Path of a Chromium (or Chrome) executable; a clear error when there is none."""
    env = os.environ.get("LENSLAB_CHROMIUM")
    if env:
        return env
    for name in CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    raise GalleryError("no Chromium browser found (looked for " + ", ".join(CANDIDATES) + "); install one, "
                       "e.g. 'apt-get install chromium', or set LENSLAB_CHROMIUM to its path")


def _run(args: list[str], timeout: float) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory(prefix="lenslab-chromium-") as profile:
        cmd = [find_chromium(), *FLAGS, f"--user-data-dir={profile}", *args]
        try:
            return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            raise GalleryError(f"Chromium did not finish within {timeout:g} s: {' '.join(cmd)}") from None


def image_states(index_html: str | os.PathLike, timeout: float = 90.0) -> list[dict]:
    """Load the page in headless Chromium and return, for every ``<img>``, its ``src``, ``naturalWidth``,
    ``naturalHeight`` and ``complete`` state once the page has loaded (``naturalWidth`` 0 = not loaded)."""
    index = Path(index_html).resolve()
    if not index.is_file():
        raise GalleryError(f"{index} does not exist; build the gallery first")
    text = index.read_text(encoding="utf-8")
    checked = text.replace("</body>", CHECK_SCRIPT + "\n</body>") if "</body>" in text else text + CHECK_SCRIPT
    fd, tmp_name = tempfile.mkstemp(prefix=".check-", suffix=".html", dir=index.parent)
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(checked)
        # the virtual-time budget lets the page finish loading (and the load handler run) before the dump
        proc = _run(["--virtual-time-budget=20000", "--dump-dom", tmp.as_uri()], timeout)
    finally:
        tmp.unlink(missing_ok=True)
    m = re.search(rf'<pre id="{RESULT_ID}">(.*?)</pre>', proc.stdout, re.S)
    if m is None:
        tail = (proc.stderr or "").strip().splitlines()[-5:]
        raise GalleryError(f"Chromium did not report the page's images (exit {proc.returncode}): "
                           + " | ".join(tail))
    return json.loads(html.unescape(m.group(1)))


def screenshot(index_html: str | os.PathLike, png: str | os.PathLike, size: tuple[int, int] = (1200, 2000),
               timeout: float = 90.0) -> Path:
    """Save a PNG screenshot of the top ``size`` (width, height) of the page."""
    index = Path(index_html).resolve()
    png = Path(png).resolve()
    png.parent.mkdir(parents=True, exist_ok=True)
    from lenslab.atomic import atomic_write_path

    with atomic_write_path(png, overwrite=True) as tmp:
        proc = _run(["--virtual-time-budget=20000", f"--screenshot={tmp}", f"--window-size={size[0]},{size[1]}",
                     index.as_uri()], timeout)
        if not Path(tmp).is_file():
            tail = (proc.stderr or "").strip().splitlines()[-5:]
            raise GalleryError(f"Chromium wrote no screenshot (exit {proc.returncode}): " + " | ".join(tail))
    return png


def check_page(index_html: str | os.PathLike, screenshot_png: str | os.PathLike | None = None) -> list[str]:
    """Problems found when the page is opened in a browser (empty list: every image loaded).

    With ``screenshot_png`` a screenshot is also saved there.
    """
    states = image_states(index_html)
    problems = [f"image {s['src']} did not load" for s in states if not s.get("naturalWidth")]
    if not states:
        problems.append("the page shows no image at all")
    if screenshot_png is not None:
        screenshot(index_html, screenshot_png)
    return problems
