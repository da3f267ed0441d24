"""The HDRI card: the user's own equirect panoramas, each warped into a couple of lenses."""

from __future__ import annotations

import time
from pathlib import Path

from gallery.page import Page, esc, fmt_seconds, section
from gallery.display import fit_within, over_card
from gallery.errors import GalleryError

SUFFIXES = (".exr", ".pfm", ".hdr")
MAX_PANORAMAS = 12
SIDE = 256  # side of the warped views, in pixels
PANO_WIDTH = 512  # width of the panorama thumbnails

#: (label, lens spec, pose) of the views made from each panorama.
VIEWS = (
    ("sky dome", "fisheye:fov=180,mapping=equisolid", {"pitch": 90.0}),
    ("little planet", "fisheye:dfov=300,mapping=stereographic", {"pitch": -90.0}),  # fills its square
)


def panorama_files(folder: Path) -> list[Path]:
    """The panoramas of a folder (EXR and PFM files), sorted by name; hidden files left out."""
    return sorted(p for p in folder.iterdir()
                  if p.is_file() and p.suffix.lower() in SUFFIXES and not p.name.startswith("."))


def hdri(page: Page, folder: Path) -> str:
    """Your own HDR panoramas, each warped into two lenses: an equisolid fisheye looking straight up (the
    sky dome, as a light probe would record it) and a little planet (a stereographic fisheye looking
    straight down, 300 degrees across its diagonal, so the planet fills its square). The warps run on the linear HDR values with
    anti-aliasing, so a small bright sun stays one small bright sun instead of a flickering pixel.

    Each panorama is tone-mapped with automatic exposure (from its log-average luminance, leaving out
    the brightest and darkest pixels), since real skies differ by many stops."""
    import numpy as np

    from lenslab.errors import FormatError
    from lenslab.io import read
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    paths = panorama_files(folder)
    if not paths:
        raise GalleryError(f"{folder} holds no panorama (.exr or .pfm); give a folder of equirect HDR images")
    # one tiny warp first, so the compile time of the warp kernels is not counted in the first view's time
    warp(np.zeros((8, 16, 3), np.float32), Camera.from_spec("equirect", (16, 8)),
         Camera.from_spec(VIEWS[0][1], (8, 8), **VIEWS[0][2]), antialias=True)
    rows, skipped = [], []
    for path in paths[:MAX_PANORAMAS]:
        try:
            image, meta = read(path)
        except (FormatError, OSError) as exc:  # one bad file in a user's folder does not stop the page
            skipped.append(f"{path.name} ({exc})")
            continue
        h, w = image.shape[:2]
        src = meta.get("camera") if isinstance(meta, dict) else None
        if src is None:
            if w != 2 * h:
                skipped.append(f"{path.name} ({w}x{h}: not a 2:1 equirect panorama and no camera in the file)")
                continue
            src = Camera.from_spec("equirect", (w, h))
        rgb = image[..., :3] if image.ndim == 3 and image.shape[-1] >= 3 else image
        exposure = "auto"
        figs = [page.save_image(f"hdri-{path.stem}", fit_within(page.tone(rgb, exposure=exposure), PANO_WIDTH))
                .figure(f"<b>{esc(path.name)}</b><br>{w}x{h}, peak {float(np.nanmax(rgb)):.4g}", cls="pano")]
        for label, spec, pose in VIEWS:
            dst = Camera.from_spec(spec, (SIDE, SIDE), **pose)
            t0 = time.perf_counter()
            out, alpha = warp(rgb, src, dst, antialias=True)
            seconds = time.perf_counter() - t0
            img = page.save_image(f"hdri-{path.stem}-{label}", over_card(page.tone(out, exposure=exposure), alpha))
            figs.append(img.figure(f"{esc(label)}, {esc(fmt_seconds(seconds))}", alt=f"{path.stem} {label}"))
        rows.append(f'<div class="figures hdri">{"".join(figs)}</div>')
    notes = []
    if len(paths) > MAX_PANORAMAS:
        notes.append(f"showing the first {MAX_PANORAMAS} of {len(paths)} panoramas")
    if skipped:
        notes.append("skipped: " + "; ".join(skipped))
    note = "".join(f'<p class="note">{esc(n)}</p>' for n in notes)
    return section("hdri", f"Your panoramas ({folder.name})", hdri, "".join(rows) + note, cls="wide")
