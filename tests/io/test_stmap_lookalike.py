"""ST maps made by other tools carry no ``lenslab:stmap`` mark: ``lenslab info`` says such a file looks like an ST
map, and how to use it, without changing how it reads it. The maps are made by the tools themselves: ffmpeg's
``geq`` writes a 16-bit PNG gradient in Nuke's STMap convention; OpenCV's ``initUndistortRectifyMap`` gives a
real undistortion's remap grid, written by OpenCV as a float TIFF (this OpenCV has no EXR writer). A marked map
given a look (``--tone``, ``--exposure``, ``--display``) to convert, which wrote it as raw codes ignoring them, is a
usage error naming the option (exit 2), before any file is written."""

from __future__ import annotations

import shutil
import subprocess

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main


def _info(path, capsys) -> list[str]:
    assert main(["info", str(path)]) == 0
    return capsys.readouterr().out.splitlines()


def _said(path) -> str:
    return (f"  looks like an ST map (R and G within [0, 1], monotone along rows and columns); give --stmap {path} "
            f"to use it (lenslab warp IMAGE --stmap {path}); its statistics above are of the file read as a picture")


@pytest.fixture
def ffmpeg_map(tmp_path):
    if shutil.which("ffmpeg") is None:
        pytest.skip("no ffmpeg")
    path = tmp_path / "ffmap.png"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "lavfi", "-i",
                    "nullsrc=s=64x48,format=gbrp16le,geq=r='(X+0.5)/W*65535':g='(1-(Y+0.5)/H)*65535':b=0",
                    "-frames:v", "1", "-pix_fmt", "rgb48be", str(path)], check=True)
    return path


def test_info_says_an_ffmpeg_16_bit_png_looks_like_an_st_map(ffmpeg_map, capsys):
    codes = cv2.imread(str(ffmpeg_map), cv2.IMREAD_UNCHANGED)  # OpenCV reads what ffmpeg wrote: BGR, 16 bits
    assert codes.dtype == np.uint16 and codes.shape == (48, 64, 3)
    # s and t at the corner pixels' centres, to a code (geq truncates its result)
    assert abs(int(codes[0, 0, 2]) - 0.5 / 64 * 65535) <= 1 and abs(int(codes[-1, 0, 1]) - 0.5 / 48 * 65535) <= 1
    lines = _info(ffmpeg_map, capsys)
    assert _said(ffmpeg_map) in lines
    # read as it always was: a 16-bit sRGB picture (its mean the sRGB decoding of ffmpeg's codes, as OpenCV gives them)
    v = codes[..., 2].astype(np.float64) / 65535
    mean = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).mean()
    stats = next(line for line in lines if line.startswith("  R "))
    assert abs(float(stats.split()[2]) - mean) < 1e-5  # (info prints 6 significant digits)


def test_info_says_an_opencv_remap_grid_looks_like_an_st_map(tmp_path, capsys):
    k = np.array([[60.0, 0, 40], [0, 60, 30], [0, 0, 1]])
    mx, my = cv2.initUndistortRectifyMap(k, np.array([-0.3, 0.1, 0, 0]), None, k, (80, 60), cv2.CV_32FC1)
    st = np.dstack([np.zeros_like(mx), 1 - (my + 0.5) / 60, (mx + 0.5) / 80]).astype(np.float32)  # B, G, R
    path = tmp_path / "undistort.tiff"
    assert cv2.imwrite(str(path), st)
    assert _said(path) in _info(path, capsys)


def test_info_does_not_say_it_of_a_picture_or_a_marked_map(tmp_path, capsys):
    rng = np.random.default_rng(3)
    photo = tmp_path / "noise.png"
    assert cv2.imwrite(str(photo), (rng.random((48, 64, 3)) * 65535).astype(np.uint16))
    assert not any("looks like an ST map" in line for line in _info(photo, capsys))
    marked = tmp_path / "map.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "64x48", "-o",
                 str(marked), "-q"]) == 0
    lines = _info(marked, capsys)
    assert not any("looks like an ST map" in line for line in lines)
    assert any(line.strip().startswith("lenslab:stmap: from fisheye") for line in lines)


@pytest.mark.parametrize("look, flag", [(["--tone", "hable"], "--tone"), (["--exposure", "1"], "--exposure"),
                                        (["--display", "sRGB - Display"], "--display")])
def test_a_marked_map_given_a_look_is_a_usage_error(tmp_path, capsys, look, flag):
    marked = tmp_path / "map.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "64x48", "-o",
                 str(marked), "-q"]) == 0
    capsys.readouterr()
    out = tmp_path / "map.png"
    assert main(["convert", str(marked), "-o", str(out), *look]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [f"lenslab convert: error: {marked}: is an ST map (its header's lenslab:stmap mark): its values "
                     f"are source positions, written as raw codes, never tone-mapped or display-encoded; drop {flag}"]
    assert not out.exists()
    assert main(["convert", str(marked), "-o", str(out), "-q"]) == 0  # without the look: its codes, as before
    codes = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    import OpenEXR

    with OpenEXR.File(str(marked)) as f:
        rgba = np.asarray(f.channels()["RGBA"].pixels, dtype=np.float64)
    assert np.abs(codes[..., 2] / 65535 - rgba[..., 0]).max() <= 0.5 / 65535 + 1e-7  # s, rounded to 16 bits


@pytest.mark.parametrize("row", [0, 255, 256, 257, 599])
def test_a_fold_in_any_row_of_a_tall_map_is_seen(row):
    """A map taller than the bands it is looked at in (256 rows): one pixel whose t goes back against its column
    (a fold, as no ST map has) is found wherever it is, the rows at the bands' seams included."""
    from lenslab.stmap_lookalike import looks_like_st_map

    h, w = 600, 8
    y, x = np.mgrid[0:h, 0:w] + 0.5
    st = np.stack([x / w, 1 - y / h], -1).astype(np.float32)
    assert looks_like_st_map(st, ["s", "t"])
    st[row, 3, 1] = st[row - 1, 3, 1] + 0.5 / h if row else st[1, 3, 1] - 0.5 / h  # against the column's way
    assert not looks_like_st_map(st, ["s", "t"])
