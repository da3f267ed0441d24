"""``lenslab warp photo.jpg --stmap map.exr``: a photo whose EXIF orientation 6 shows it 300 x 400 while the
camera stored it 400 x 300. A map made by ``lenslab stmap`` for the stored frame (its mark records 400x300) warps
the stored image; a map made for the photo as shown warps it as shown; a map of another shape is refused in one
line naming both sizes (exit 1), where the warp used to stretch the image silently. A map made by another tool
(no mark; here written by OpenEXR's own bindings) is placed by its own size.

Oracles: Pillow writes the photo with its orientation; OpenCV's ``imread(IMREAD_UNCHANGED)`` gives the stored
frame (it ignores the orientation), Pillow's ``ImageOps.exif_transpose`` the frame as shown; the expected output is
OpenCV's ``remap`` (bilinear, edge replicated, as lenslab's taps clamp) of that frame's linear values at the map's
pixel positions, ``x = s W - 1/2`` and ``y = (1 - t) H - 1/2`` (Nuke's STMap convention, transcribed here)."""

from __future__ import annotations

import cv2
import numpy as np
import OpenEXR
import pytest
from PIL import Image, ImageOps

from lenslab.cli.main import main

STORED = (400, 300)  # (W, H) of the camera's pixels


def _srgb_to_linear(codes: np.ndarray) -> np.ndarray:
    """IEC 61966-2-1's decoding, in float64."""
    v = codes.astype(np.float64) / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


@pytest.fixture
def photo(tmp_path):
    """A smooth 400 x 300 picture stored with EXIF orientation 6 (shown turned 90 degrees clockwise)."""
    y, x = np.mgrid[0:STORED[1], 0:STORED[0]].astype(np.float64)
    rgb = np.stack([x / (STORED[0] - 1), y / (STORED[1] - 1), 0.5 + 0.4 * np.sin(x / 37.0) * np.cos(y / 23.0)], -1)
    im = Image.fromarray(np.round(rgb * 255).astype(np.uint8))
    exif = im.getexif()
    exif[0x0112] = 6
    path = tmp_path / "photo.jpg"
    im.save(path, quality=100, exif=exif.tobytes())
    return path


def _read_exr(path) -> np.ndarray:
    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        if "RGBA" in ch:
            return np.asarray(ch["RGBA"].pixels, dtype=np.float64)
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGBA"], -1)


def _expected(frame_rgb: np.ndarray, st: np.ndarray) -> tuple[np.ndarray, float]:
    """OpenCV's bilinear remap of the frame's linear values by the map, and the tolerance: cv2.remap places each
    position to 1/32 of a pixel (its INTER_TAB_SIZE), so it may differ by 1/32 of the largest step between
    neighbouring pixels (plus float32 rounding)."""
    lin = _srgb_to_linear(frame_rgb).astype(np.float32)
    h, w = lin.shape[:2]
    mx = (st[..., 0] * w - 0.5).astype(np.float32)
    my = ((1.0 - st[..., 1]) * h - 0.5).astype(np.float32)
    out = cv2.remap(lin, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    step = max(np.abs(np.diff(lin, axis=0)).max(), np.abs(np.diff(lin, axis=1)).max())
    return out.astype(np.float64), step / 32 + 1e-5


def _make_map(tmp_path, name: str, source: tuple[int, int]):
    path = tmp_path / name
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "160x120",
                 "--source-size", f"{source[0]}x{source[1]}", "-o", str(path), "-q"]) == 0
    return path


def _warp(photo, st_path, tmp_path, name="out.exr") -> np.ndarray:
    out = tmp_path / name
    assert main(["warp", str(photo), "--stmap", str(st_path), "-o", str(out), "--pixel-type", "float", "-q"]) == 0
    return _read_exr(out)


def _stored(photo) -> np.ndarray:
    bgr = cv2.imread(str(photo), cv2.IMREAD_UNCHANGED)
    assert bgr.shape == (STORED[1], STORED[0], 3)  # OpenCV: the stored frame, orientation not applied
    return bgr[..., ::-1]


def test_a_map_of_the_stored_frame_warps_the_stored_image(photo, tmp_path):
    st_path = _make_map(tmp_path, "stored.exr", STORED)
    st = _read_exr(st_path)
    want, tol = _expected(_stored(photo), st)
    got = _warp(photo, st_path, tmp_path)
    seen = st[..., 3] > 0.5
    assert seen.all() and got.shape == (120, 160, 4)
    assert np.abs(got[..., :3] - want).max() <= tol
    # and it is not the warp of the photo as shown, stretched (what was written before)
    shown = np.asarray(ImageOps.exif_transpose(Image.open(photo)))
    stretched, _ = _expected(shown, st)
    assert np.abs(got[..., :3] - stretched).max() > 0.1


def test_a_map_of_the_shown_frame_warps_the_photo_as_shown(photo, tmp_path):
    st_path = _make_map(tmp_path, "shown.exr", STORED[::-1])
    shown = np.asarray(ImageOps.exif_transpose(Image.open(photo)))  # Pillow turns it as viewers show it
    assert shown.shape == (STORED[0], STORED[1], 3)
    want, tol = _expected(shown, _read_exr(st_path))
    assert np.abs(_warp(photo, st_path, tmp_path)[..., :3] - want).max() <= tol


def test_a_map_of_another_shape_is_refused_in_one_line(photo, tmp_path, capsys):
    st_path = _make_map(tmp_path, "wide.exr", (500, 300))
    out = tmp_path / "out.exr"
    assert main(["warp", str(photo), "--stmap", str(st_path), "-o", str(out)]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "500x300 source" in lines[0] and "this image is 300x400 (400x300 as stored" in lines[0]
    assert not out.exists()


def test_a_map_of_the_same_shape_at_another_size_still_applies(photo, tmp_path):
    """ST maps hold fractions of the source's size: a map of an 800 x 600 plate applies to its 400 x 300 proxy."""
    st_path = _make_map(tmp_path, "double.exr", (800, 600))
    want, tol = _expected(_stored(photo), _read_exr(st_path))
    assert np.abs(_warp(photo, st_path, tmp_path)[..., :3] - want).max() <= tol


def test_an_unmarked_map_of_the_stored_size_warps_the_stored_image(photo, tmp_path):
    """A map from another tool, written with OpenEXR's bindings: the stored frame shifted 10.25 pixels right and
    3.5 down, 400 x 300 (the stored size, not the shown 300 x 400)."""
    w, h = STORED
    y, x = np.mgrid[0:h, 0:w] + 0.5
    s = ((x + 10.25) / w).astype(np.float32)
    t = (1.0 - (y + 3.5) / h).astype(np.float32)
    st_path = tmp_path / "nuke.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"R": s, "G": t, "B": np.zeros_like(s)}) as f:
        f.write(str(st_path))
    st = np.stack([s, t, np.zeros_like(s), np.ones_like(s)], -1).astype(np.float64)
    want, tol = _expected(_stored(photo), st)
    got = _warp(photo, st_path, tmp_path)
    inside = (x + 10.25 < w) & (y + 3.5 < h)  # (without alpha, entries within [0, 1] count)
    assert np.abs(got[..., :3] - want)[inside].max() <= tol


def test_a_half_turn_keeps_the_size_so_the_map_applies_as_shown_with_a_note(tmp_path, capsys):
    """Orientation 3 (a half turn) keeps 400 x 300: the sizes cannot tell the frames apart, so the map is applied to
    the photo as shown (Pillow's ``exif_transpose``), and one note says so."""
    y, x = np.mgrid[0:STORED[1], 0:STORED[0]].astype(np.float64)
    im = Image.fromarray(np.round(np.stack([x / 399, y / 299, 0.5 + 0 * x], -1) * 255).astype(np.uint8))
    exif = im.getexif()
    exif[0x0112] = 3
    photo = tmp_path / "half.jpg"
    im.save(photo, quality=100, exif=exif.tobytes())
    st_path = _make_map(tmp_path, "map.exr", STORED)
    capsys.readouterr()
    shown = np.asarray(ImageOps.exif_transpose(Image.open(photo)))
    want, tol = _expected(shown, _read_exr(st_path))
    out = tmp_path / "out.exr"
    assert main(["warp", str(photo), "--stmap", str(st_path), "-o", str(out), "--pixel-type", "float"]) == 0
    assert np.abs(_read_exr(out)[..., :3] - want).max() <= tol
    notes = [line for line in capsys.readouterr().err.splitlines() if "EXIF orientation 3" in line]
    assert len(notes) == 1 and "fits it both as stored and as shown" in notes[0] and "as shown" in notes[0]
