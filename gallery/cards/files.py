"""The files card: every file a run wrote, with its format and size."""

from __future__ import annotations

from gallery.page import Page, esc, fmt_bytes, section
from gallery.items import FileList


def files(page: Page, item: FileList) -> str:
    """Every file this run wrote, in each format lenslab reads and writes: EXR and PFM keep linear HDR
    values (EXR files also carry their camera, so ``lenslab info`` shows the lens and a later warp can
    start from it); JPG and PPM hold tone-mapped, sRGB-encoded display images.

    Open any of them with ``lenslab info FILE``, or warp one again with ``lenslab warp``."""
    rows = []
    for f in item.files:
        path = page.path(f["path"])
        size = fmt_bytes(path.stat().st_size) if path.is_file() else "missing"
        rows.append(
            f'<tr><td><a href="{esc(f["path"])}">{esc(f["path"])}</a></td><td>{esc(f.get("format", ""))}</td>'
            f'<td class="num">{esc(size)}</td><td>{esc(f.get("what", ""))}</td></tr>'
        )
    body = ('<table class="files"><thead><tr><th>file</th><th>format</th><th>size</th><th>what</th></tr></thead>'
            f"<tbody>{''.join(rows)}</tbody></table>")
    return section("files", "Files written", files, body, cls="wide")
