"""``python -m gallery DIR --check`` checks an existing page as it stands: no --overwrite needed, nothing
rebuilt, and an older screenshot is kept unless --overwrite is given."""

from __future__ import annotations

import pytest

import gallery.browser
from gallery.__main__ import main
from gallery.build import build_gallery
from tests.gallery.test_gallery_page import stand_in_records


@pytest.fixture()
def page(tmp_path, monkeypatch):
    index = build_gallery(tmp_path, *stand_in_records(tmp_path), title="check")
    calls = []

    def fake_check(index_html, screenshot_png=None):  # the browser's part is tested in test_gallery_page
        calls.append((str(index_html), screenshot_png))
        if screenshot_png is not None:
            screenshot_png.write_bytes(b"png")
        return []

    monkeypatch.setattr(gallery.browser, "check_page", fake_check)
    return index, calls


def test_check_needs_no_overwrite_and_leaves_the_page_alone(page, capsys):
    index, calls = page
    before, mtime = index.read_bytes(), index.stat().st_mtime_ns
    assert main([str(index.parent), "--check", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "all images loaded" in out and "gallery:" not in out  # checked, not rebuilt
    assert index.read_bytes() == before and index.stat().st_mtime_ns == mtime
    assert calls == [(str(index), index.parent / "screenshot.png")]
    # a second check keeps the screenshot the first one saved; --overwrite rebuilds, then replaces it
    assert main([str(index.parent), "--check", "--quiet"]) == 0
    assert calls[-1][1] is None and "is kept" in capsys.readouterr().out
    assert main([str(index.parent), "--check", "--quiet", "--overwrite"]) == 0
    assert calls[-1][1] == index.parent / "screenshot.png" and "gallery:" in capsys.readouterr().out


def test_rebuilding_still_needs_overwrite(page):
    index, _ = page
    assert main([str(index.parent), "--quiet"]) == 1  # the page exists: replaced only with --overwrite
    assert main([str(index.parent), "--quiet", "--check", "--title", "new"]) == 1  # a change is a rebuild
