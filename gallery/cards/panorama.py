"""The panorama card: the HDR panorama every other view is warped from."""

from __future__ import annotations

from gallery.page import Page, facts_table, fmt_seconds, section
from gallery.display import fit_within
from gallery.items import Panorama

WIDTH = 1024  # widest image on the page, in pixels


def panorama(page: Page, item: Panorama) -> str:
    """One trace of the whole sphere around the eye, stored as linear HDR (EXR, with its camera in the
    header). Every lens view below is warped from this single image: one trace, many lenses.

    Shown here with the page's tone curve; the file itself keeps the full range (the ceiling light is
    many times brighter than the walls)."""
    image = page.read(item.path)
    img = page.save_image("panorama", fit_within(page.tone(image), WIDTH))
    w, h = item.size
    rows = [
        ("scene", item.scene or None),
        ("camera", item.spec),
        ("size", f"{w} x {h}"),
        ("eye", None if item.eye is None else "(" + ", ".join(f"{v:g}" for v in item.eye) + ")"),
        ("integrator", f"{item.integrator}, max depth {item.max_depth}" if item.integrator else None),
        ("samples per pixel", item.spp or None),
        ("trace time", fmt_seconds(item.seconds) if item.seconds else None),
        ("display", f"{page.display.curve}, exposure {page.display.exposure:+.2f} EV"),
        ("file", item.path),
    ]
    body = f'<div class="figures wide">{img.figure("equirect panorama, tone-mapped for display")}</div>' + facts_table(rows)
    return section("panorama", "The panorama", panorama, body, cls="wide")
