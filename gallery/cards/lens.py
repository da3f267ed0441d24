"""The lens cards: every view warped from the panorama, and the views checked against a direct trace."""

from __future__ import annotations

from gallery.page import Img, Page, esc, facts_table, fmt_percent, fmt_seconds, section, slug
from gallery.display import DIFF_SCALE, colour_map, difference, fit_within, legend_gradient
from gallery.items import LensView

SIDE = 400  # largest side of a view on the page, in pixels

ERROR_LABELS = {
    "l1": "relative L1 error, warped vs direct",
    "l1_interior": "relative L1 away from edges",
    "l1_edge": "relative L1 within 2 px of edges",
    "noise_l1": "the direct trace's own noise (expected L1)",
    "excess_l1": "error beyond that noise",
    "psnr_log": "PSNR of log radiance",
    "flip": "FLIP (tone-mapped)",
    "off5": "pixels off by more than 5%",
}


def _pose(view: LensView) -> str | None:
    if not view.pose:
        return None
    return ", ".join(f"{k} {v:g}" if isinstance(v, (int, float)) else f"{k} {v}" for k, v in view.pose.items())


def _settings(view: LensView) -> str | None:
    if not view.settings:
        return None
    return ", ".join(f"{k}={v}" for k, v in view.settings.items())


def _error_value(key: str, value) -> str:
    if value is None:
        return "-"
    if key in ("psnr_log",):
        return f"{value:.1f} dB"
    if key in ("flip",):
        return f"{value:.4f}"
    return fmt_percent(value)


def lens_comparisons(page: Page, views: list[LensView]) -> str:
    """The same cameras made two ways: warped from the panorama (left) and traced directly (middle).
    The difference map (right) shows, per pixel, the mean absolute difference over the three colour
    channels divided by the direct image's mean radiance, so its average is the relative L1 error
    below; grey pixels are outside the lens's image.

    Both renders are Monte Carlo estimates, so part of the difference is noise rather than the warp:
    beside the error stands the error the direct trace's own noise alone would give against a perfect
    image, and what remains beyond it. The speed-up is the direct trace's time over the warp's; the
    panorama is traced once for every view."""
    blocks = "".join(_comparison(page, v) for v in views)
    return section("compare", "Warped vs traced directly", lens_comparisons, blocks, cls="wide")


def _comparison(page: Page, view: LensView) -> str:
    warped = page.read(view.warped)
    direct = page.read(view.direct)
    key = slug(view.name)
    w_img = page.save_image(f"{key}-warped", fit_within(page.tone(warped), SIDE))
    d_img = page.save_image(f"{key}-direct", fit_within(page.tone(direct), SIDE))
    d, valid, mean = difference(warped, direct)
    diff_rgb = colour_map(d, valid)
    diff_img = page.save_image(f"{key}-difference", fit_within(diff_rgb, SIDE), encoded=True)
    legend = (f'<div class="legend"><span>0</span><span class="bar" style="background: {legend_gradient()}"></span>'
              f"<span>{DIFF_SCALE * 100:.0f}% of mean radiance</span></div>")
    spp = f", {view.trace_spp} spp" if view.trace_spp else ""
    figs = (
        w_img.figure(f"warped from the panorama, {esc(fmt_seconds(view.warp_seconds))}")
        + d_img.figure(f"traced directly{esc(spp)}, {esc(fmt_seconds(view.trace_seconds))}")
        + diff_img.figure(f"difference, mean {esc(fmt_percent(mean))}", extra=legend)
    )
    rows = [("lens", view.spec), ("size", f"{view.size[0]} x {view.size[1]}"), ("pose", _pose(view)),
            ("warp settings", _settings(view))]
    for k, v in (view.error or {}).items():
        rows.append((ERROR_LABELS.get(k, k.replace("_", " ")), _error_value(k, v)))
    rows += [("warp time", fmt_seconds(view.warp_seconds)), ("direct trace time", fmt_seconds(view.trace_seconds))]
    if view.trace_seconds and view.warp_seconds:
        rows.append(("speed-up of the warp", f"{view.trace_seconds / view.warp_seconds:.0f}x"))
    note = f'<p class="note">{esc(view.note)}</p>' if view.note else ""
    body = f'<div class="figures three">{figs}</div>{note}{facts_table(rows)}'
    return f'<div class="comparison"><h3>{esc(view.name)}</h3>{body}</div>'


def on_card(page: Page, image):
    """Tone-mapped premultiplied colour over the card's background, by the image's alpha (display-linear)."""
    from gallery.display import over_card, split_alpha

    return over_card(page.tone(image), split_alpha(image)[1])


def _tile(page: Page, view: LensView) -> str:
    img: Img = page.save_image(f"view-{slug(view.name)}", fit_within(on_card(page, page.read(view.warped)), SIDE))
    details = [f"<code>{esc(view.spec)}</code>"]
    if view.pose:
        details.append(esc(_pose(view)))
    details.append(f"{view.size[0]}x{view.size[1]}, warped in {esc(fmt_seconds(view.warp_seconds))}")
    if view.note:
        details.append(f'<span class="note">{esc(view.note)}</span>')
    caption = f"<b>{esc(view.name)}</b><br>" + "<br>".join(details)
    return img.figure(caption, alt=view.name)


def lens_views(page: Page, views: list[LensView]) -> str:
    """Every lens model lenslab knows, each warped from the one panorama. For every output pixel the
    lens gives a ray direction, the panorama is sampled along it with an anti-aliasing filter, and the
    share of the pixel that the lens actually covers becomes its alpha, so the corners outside a fisheye's
    circle are transparent rather than smeared.

    Each picture has the shape of what its lens sees: where a lens has no ray (outside a fisheye's
    circle, around a Hammer ellipse) the card shows through. The tiled view is four cameras sharing the
    panorama's eye, each with its own pose, as in the 2x2 multi-view; the little planet is a
    stereographic fisheye looking straight down, its field across the diagonal so the planet fills
    the frame."""
    tiles = "".join(_tile(page, v) for v in views)
    return section("lenses", "Every lens, warped from one panorama", lens_views, f'<div class="figures grid">{tiles}</div>',
                   cls="wide")
