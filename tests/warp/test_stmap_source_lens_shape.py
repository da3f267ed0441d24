"""``lenslab warp IMAGE --stmap MAP`` of a map whose ``lenslab:stmap`` mark records a source of another shape than
the image: refused only where the source lens reads other fractions of a frame of that shape (a fisheye, a
perspective view, a lensfun lens: the image would be stretched), never for a lens whose fractions are the same
directions whatever its frame (an equirect, a cube map). ``lenslab stmap --size 64x64`` without ``--source-size``
records a 64 x 64 source; its map of an equirect source applies unchanged to a 2:1 panorama.

Oracles: OpenCV's ``remap`` (bilinear, edge replicated) of the image at the map's positions ``x = s W - 1/2``,
``y = (1 - t) H - 1/2`` (Nuke's STMap convention, transcribed here); the equirect fractions of a direction, ``s =
1/2 + lon / 360``, ``1 - t = 1/2 - lat / 180`` in float64, for the map itself; and the lensfun database
(lensfunpy) for a lens whose name holds spaces."""

from __future__ import annotations

import cv2
import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from tests.warp.test_stmap_turned_photo import _read_exr


def _panorama(path, w: int = 128, h: int = 64) -> np.ndarray:
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    image = np.stack([x / w, y / h, 0.5 + 0.4 * np.sin(x / 7.0) * np.cos(y / 5.0)], -1).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": image}) as f:  # written by OpenEXR's own bindings
        f.write(str(path))
    return image


def _assert_warped_as_remap(src, image: np.ndarray, st_path, tmp_path) -> None:
    """``lenslab warp SRC --stmap MAP`` writes OpenCV's remap of ``image`` at the map's positions where it sees."""
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "--stmap", str(st_path), "-o", str(out), "--pixel-type", "float", "-q"]) == 0
    st = _read_exr(st_path)
    h, w = image.shape[:2]
    want = cv2.remap(image, (st[..., 0] * w - 0.5).astype(np.float32), ((1 - st[..., 1]) * h - 0.5).astype(np.float32),
                     cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    step = max(np.abs(np.diff(image, axis=0)).max(), np.abs(np.diff(image, axis=1)).max())
    seen = st[..., 3] > 0.5
    assert seen.mean() > 0.5  # (most of the output sees the source: the comparison is not empty)
    assert np.abs(_read_exr(out)[..., :3] - want)[seen].max() <= step / 32 + 1e-5  # cv2.remap's 1/32-pixel positions


def test_an_equirect_map_made_without_source_size_applies_to_a_2_to_1_panorama(tmp_path):
    pano = tmp_path / "pano.exr"
    image = _panorama(pano)
    st_path = tmp_path / "map.exr"
    assert main(["stmap", "--from", "equirect", "--to", "perspective:fov=90", "--yaw", "30", "--size", "64x64",
                 "-o", str(st_path), "-q"]) == 0
    st = _read_exr(st_path)
    # the map is right for any equirect: the output's centre ray (yaw 30, on the horizon) is at lon 30, lat 0
    c = st[31:33, 31:33, :2].mean(axis=(0, 1))
    assert abs(c[0] - (0.5 + 30 / 360)) < 1e-4 and abs(c[1] - 0.5) < 1e-4  # (float32 fractions, a pixel's 1/64)
    _assert_warped_as_remap(pano, image, st_path, tmp_path)


def test_a_cube_map_source_of_another_shape_applies(tmp_path):
    """A cube map's fractions are its faces' whatever its size: a map made for a 96 x 96 cube map applies to a
    96 x 64 one (3x2 faces of 32)."""
    src = tmp_path / "cube.exr"
    image = _panorama(src, 96, 64)
    st_path = tmp_path / "map.exr"
    assert main(["stmap", "--from", "cubemap", "--to", "fisheye:fov=180", "--size", "48x48", "--source-size", "96x96",
                 "-o", str(st_path), "-q"]) == 0
    _assert_warped_as_remap(src, image, st_path, tmp_path)


def test_a_fisheye_map_of_another_shape_is_still_refused(tmp_path, capsys):
    pano = tmp_path / "wide.exr"
    _panorama(pano)
    st_path = tmp_path / "map.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "64x64",
                 "-o", str(st_path), "-q"]) == 0
    assert main(["warp", str(pano), "--stmap", str(st_path), "-o", str(tmp_path / "out.exr")]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "made for a 64x64 source" in lines[0] and "this image is 128x64" in lines[0]


def test_a_lensfun_source_whose_name_holds_spaces_is_read_from_the_mark(tmp_path, capsys):
    import lensfunpy
    name = "Canon EF 8-15mm f/4L Fisheye USM"
    assert name in {lens.model for lens in lensfunpy.Database().lenses}  # a name with spaces, as the database has it
    st_path = tmp_path / "map.exr"
    assert main(["stmap", "--from", f"lensfun:lens={name},focal=15", "--to", "perspective:fov=90", "--size", "30x20",
                 "--source-size", "96x64", "-o", str(st_path), "-q"]) == 0
    square = tmp_path / "square.exr"
    _panorama(square, 64, 64)  # another shape than the 3:2 frame the map is made for
    assert main(["warp", str(square), "--stmap", str(st_path), "-o", str(tmp_path / "out.exr")]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "made for a 96x64 source" in lines[0] and "this image is 64x64" in lines[0]


@pytest.mark.parametrize("recorded", ["0x0", "0x64", "128x0"])
def test_a_mark_recording_no_pixels_is_read_as_no_mark(tmp_path, recorded):
    """A header whose mark records a source of no pixels (written by hand, or damaged) says nothing of the source: the
    map applies by its values, as another tool's does, never a division by zero."""
    pano = tmp_path / "pano.exr"
    image = _panorama(pano)
    h, w = 32, 32
    y, x = np.mgrid[0:h, 0:w] + 0.5
    s, t = (x / w).astype(np.float32), (1.0 - y / h).astype(np.float32)
    st_path = tmp_path / "map.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "lenslab:stmap": f"from equirect {recorded} to equirect 32x32"}
    with OpenEXR.File(header, {"R": s, "G": t, "B": np.zeros_like(s), "A": np.ones_like(s)}) as f:
        f.write(str(st_path))
    _assert_warped_as_remap(pano, image, st_path, tmp_path)
