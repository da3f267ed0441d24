"""The tone cards: one HDR image under every tone curve, and the curves themselves on one chart."""

from __future__ import annotations

from gallery.page import Page, esc, section
from gallery.display import fit_within
from gallery.items import ToneSet

SIDE = 300  # largest side of a strip image on the page, in pixels


def _summary(curve: str) -> str:
    """The curve's one-line summary from the tone-curve registry."""
    from lenslab.tone import CURVES

    c = CURVES.get(curve)
    text = (c.summary if c is not None else "").replace("``", "")
    if len(text) > 80:  # a caption, not the whole reference: cut at a word
        text = text[:80].rsplit(" ", 1)[0] + "\u2026"
    return text


def tone_strip(page: Page, item: ToneSet) -> str:
    """The same HDR image through each tone curve, at the same exposure. ``clamp`` is the original
    renderer's behaviour (everything above 1 turns white); ``hable`` (Uncharted 2) is the curve it
    finally chose and lenslab's default; the others trade contrast, saturation and highlight roll-off
    differently.

    Choose one with ``--tone CURVE`` on ``convert``, ``warp`` and ``tonemap``, or compare your own image
    with ``lenslab compare-tones IMAGE -o strip.jpg``."""
    image = page.read(item.source)
    figs = []
    for curve in item.curves:
        img = page.save_image(f"tone-{curve}", fit_within(page.tone(image, curve, item.exposure), SIDE))
        summary = _summary(curve)
        extra = f'<br><span class="note">{esc(summary)}</span>' if summary else ""
        figs.append(img.figure(f"<b>{esc(curve)}</b>", alt=f"{curve} tone curve", extra=extra))
    label = f" ({esc(item.label)})" if item.label else ""
    body = (f'<div class="figures strip">{"".join(figs)}</div>'
            f'<p class="note">exposure {item.exposure:+.2f} EV{label}</p>')
    return section("tone", "Tone curves, side by side", tone_strip, body, cls="wide")


def tone_curves(page: Page, item: ToneSet | None = None) -> str:
    """Every tone curve on one chart: scene-linear input in stops (a log axis) against what the viewer
    sees (left, sRGB-encoded) and the display-linear output (right). Curves that reach white early burn
    highlights out; curves that approach it slowly keep detail in lights and skies at the cost of
    contrast. drago and mantiuk depend on the whole image, so they are drawn (dashed) as their response
    to a ramp. ``lenslab curves -o curves.png`` draws this chart."""
    from lenslab.atomic import atomic_write_path
    from lenslab.tone.plot import plot_curves

    path, rel = page.new_image_path("tone-curves", "png")
    names = list(item.curves) if item is not None else None
    exposure = float(item.exposure) if item is not None else 0.0
    fig = plot_curves(names, stops=(-10.0, 8.0), exposure=exposure)
    with atomic_write_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    img = page.written_image(rel)
    return section("curves", "The tone curves", tone_curves,
                   f'<div class="figures wide">{img.figure(f"tone curves at exposure {exposure:+.2f} EV")}</div>',
                   cls="wide")
