"""MkDocs hooks of the documentation site (named in mkdocs.yml under ``hooks:``).

- Pages that come and go with features (``docs/cameras.md``, ``docs/lenses.md``, ...) join the nav when
  their file exists; any other page under ``docs/`` that the nav does not name is listed under "More",
  so a new page is never left out and a missing one never breaks the strict build.
- ``docs/speed.md`` gets its table from the benchmark records in ``bench-results/`` (the same
  ``tools/speed_table.py`` that prints it), between ``<!-- speed-table:start -->`` and ``<!-- speed-table:end -->``.
- The README's pictures (``gallery/images/*.jpg``) are served as ``images/*.jpg`` without a copy in ``docs/``.
- A link from a page to a file of the repository outside ``docs/`` (``../lenslab/warp/engine.py``)
  becomes that file's path in code type: the site is read without the source tree beside it. A
  picture from ``../gallery/images/`` is shown from the site's copy.
"""

from __future__ import annotations

import json
import posixpath
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: optional pages: file -> (nav section, title); each joins its section when the file exists
OPTIONAL = {
    "cameras.md": ("User guide", "Camera files and calibration"),
    "stereo.md": ("User guide", "Stereo 360"),
    "lenses.md": ("Reference", "Lens models"),
    "robustness.md": ("Reference", "Robustness: hostile files"),
    "design.md": ("Reference", "Design"),
}
GENERATED = ("examples/",)  # written by the build itself (mkdocs-gallery)
LINK = re.compile(r"(?<!!)\[([^\]]+)\]\(([^)\s]+)\)")
IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)")


def _named(nav) -> set[str]:
    out: set[str] = set()
    for item in nav or []:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        if isinstance(value, list):
            out |= _named(value)
        elif isinstance(value, str):
            out.add(value)
    return out


def _section(nav: list, title: str) -> list:
    for item in nav:
        if isinstance(item, dict) and title in item and isinstance(item[title], list):
            return item[title]
    entries: list = []
    nav.insert(len(nav) - 1, {title: entries})
    return entries


def on_config(config, **kwargs):
    docs = Path(config["docs_dir"])
    nav = config["nav"]
    named = _named(nav)
    for page, (section, title) in OPTIONAL.items():
        if page not in named and (docs / page).is_file():
            _section(nav, section).append({title: page})
            named.add(page)
    extra = sorted(p.relative_to(docs).as_posix() for p in docs.rglob("*.md"))
    extra = [p for p in extra if p not in named and not p.startswith(GENERATED) and p != "README.md"]
    if extra:
        _section(nav, "More").extend(extra)
    return config


def on_files(files, config, **kwargs):
    from mkdocs.structure.files import File

    for jpg in sorted((ROOT / "gallery" / "images").glob("*.jpg")):
        files.append(File(f"images/{jpg.name}", str(jpg.parent.parent), config["site_dir"],
                          config["use_directory_urls"]))
    return files


def _speed_tool():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import speed_table
    finally:
        sys.path.pop(0)
    return speed_table


def speed_table() -> str:
    table = _speed_tool().table
    files = sorted((ROOT / "bench-results").glob("*.json"))
    if not files:
        return "*No benchmark records in `bench-results/` yet: run `lenslab bench TARGET --json FILE`.*\n"
    return table([json.loads(f.read_text(encoding="utf-8")) for f in files])


def _outside_links(markdown: str, page_path: str) -> str:
    here = posixpath.dirname(page_path)

    def fix(m: re.Match) -> str:
        text, target = m.group(1), m.group(2)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith(("#", "/")):
            return m.group(0)
        path = posixpath.normpath(posixpath.join(here, target.split("#")[0]))
        if not path.startswith("../"):
            return m.group(0)
        repo_path = path[3:]
        return text if text.strip("`") == repo_path else f"{text} (`{repo_path}`)"

    def picture(m: re.Match) -> str:  # the README's pictures, served as images/NAME (see on_files)
        target = posixpath.normpath(posixpath.join(here, m.group(2)))
        if not target.startswith("../gallery/images/"):
            return m.group(0)
        served = posixpath.relpath(f"images/{posixpath.basename(target)}", here or ".")
        return f"![{m.group(1)}]({served})"

    return IMAGE.sub(picture, LINK.sub(fix, markdown))


def _fill_speed(markdown: str) -> str:
    tool = _speed_tool()
    start, end = tool.START, tool.END
    if start not in markdown or end not in markdown:
        return markdown
    head, rest = markdown.split(start, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{start}\n{speed_table()}{end}{tail}"


def on_page_markdown(markdown, page, config, files, **kwargs):
    return _outside_links(_fill_speed(markdown), page.file.src_uri)
