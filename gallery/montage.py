"""Small montages of a built gallery, for a README: a few JPGs that each stay under a byte budget.

``readme_images(gallery_dir, dest)`` reads the page images a demo gallery wrote under ``img/`` and
writes, under ``dest``:

- ``panorama.jpg``: the traced panorama;
- ``lenses.jpg``: a grid of eight lens views;
- ``compare.jpg``: warped, traced and difference map of a compared view (the equisolid fisheye if shown);
- ``tones.jpg``: a row of tone curves;
- ``hdri.jpg``: sky dome and little planet of the first panoramas of an HDRI folder, when the page has them.

Each is re-encoded at the highest JPG quality that fits ``max_bytes``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gallery.errors import GalleryError

MAX_BYTES = 60_000
#: the lens views shown in the README montage, in order (file names of the page's view images)
FEATURED = ("fisheye-equisolid", "fisheye-stereographic", "tan-warped-fisheye", "little-planet",
            "swirl", "pincushion", "2x2-multi-view", "cube-map")
GAP = 4  # pixels between montage tiles
BACKGROUND = (0x1F / 255, 0x22 / 255, 0x26 / 255)  # display-encoded: the page's card colour, behind the lenses' tiles


def _load(path: Path) -> np.ndarray:
    import cv2

    im = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if im is None:
        raise GalleryError(f"{path} is missing or not an image; build the gallery again")
    return (im[..., ::-1].astype(np.float32) / 255.0)  # display-encoded RGB in [0, 1]


def _fit(im: np.ndarray, side: int) -> np.ndarray:
    """Resize so the longer side is ``side`` (area filter when shrinking)."""
    import cv2

    h, w = im.shape[:2]
    s = side / max(h, w)
    size = (max(1, round(w * s)), max(1, round(h * s)))
    return cv2.resize(im, size, interpolation=cv2.INTER_AREA if s < 1 else cv2.INTER_CUBIC)


def grid(tiles: list[np.ndarray], cols: int, side: int) -> np.ndarray:
    """Tiles (each fitted into a ``side`` square, centred) in a grid of ``cols`` columns."""
    rows = (len(tiles) + cols - 1) // cols
    out = np.full((rows * side + (rows - 1) * GAP, cols * side + (cols - 1) * GAP, 3), BACKGROUND, np.float32)
    for i, t in enumerate(tiles):
        t = _fit(t, side)
        r, c = divmod(i, cols)
        y0 = r * (side + GAP) + (side - t.shape[0]) // 2
        x0 = c * (side + GAP) + (side - t.shape[1]) // 2
        out[y0:y0 + t.shape[0], x0:x0 + t.shape[1]] = t
    return out


def write_within(path: Path, image: np.ndarray, max_bytes: int = MAX_BYTES) -> Path:
    """Write a display-encoded RGB image as JPG at the best quality (95 down to 40) under ``max_bytes``."""
    from lenslab.io import write

    for quality in range(95, 35, -5):
        write(path, image, raw=True, quality=quality, overwrite=True)
        if path.stat().st_size <= max_bytes:
            return path
    raise GalleryError(f"{path}: cannot fit {image.shape[1]}x{image.shape[0]} into {max_bytes} bytes; "
                       "make the montage smaller")


MONTAGES = ("panorama.jpg", "lenses.jpg", "compare.jpg", "tones.jpg", "hdri.jpg")  # what readme_images writes


def readme_images(gallery_dir: str | Path, dest: str | Path, max_bytes: int = MAX_BYTES) -> list[Path]:
    """Write the README montages of a demo gallery into ``dest``; returns the files written."""
    src = Path(gallery_dir) / "img"
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    if not src.is_dir():
        raise GalleryError(f"{gallery_dir} has no img/ folder; run 'lenslab demo -o {gallery_dir}' first")
    written = []
    if (src / "panorama.jpg").is_file():
        written.append(write_within(dest / "panorama.jpg", _fit(_load(src / "panorama.jpg"), 800), max_bytes))
    views = [src / f"view-{name}.jpg" for name in FEATURED]
    views = [p for p in views if p.is_file()] or sorted(src.glob("view-*.jpg"))[:8]
    if views:
        written.append(write_within(dest / "lenses.jpg", grid([_load(p) for p in views], 4, 190), max_bytes))
    diffs = sorted(src.glob("*-difference.jpg"), key=lambda p: (not p.name.startswith(FEATURED[0]), p.name))
    if diffs:
        key = diffs[0].name[: -len("-difference.jpg")]
        trio = [_load(src / f"{key}-{part}.jpg") for part in ("warped", "direct", "difference")]
        written.append(write_within(dest / "compare.jpg", grid(trio, 3, 256), max_bytes))
    tones = [src / f"tone-{c}.jpg" for c in ("clamp", "reinhard", "hable", "aces", "agx", "pbr-neutral")]
    tones = [p for p in tones if p.is_file()]
    if tones:
        written.append(write_within(dest / "tones.jpg", grid([_load(p) for p in tones], len(tones), 150), max_bytes))
    planets = sorted(src.glob("hdri-*-little-planet.jpg"))[:3]
    domes = sorted(src.glob("hdri-*-sky-dome.jpg"))[:3]
    if planets:
        written.append(write_within(dest / "hdri.jpg", grid([_load(p) for p in planets + domes], len(planets), 200),
                                    max_bytes))
    return written
