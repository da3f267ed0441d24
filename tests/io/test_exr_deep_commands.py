"""Commands on the deep Trunks files: ``info`` describes each deep part (its samples: total, most in one
pixel, pixels with any) instead of refusing it, ``warp`` and ``convert`` take them, and a part of the deep
stereo file is picked by index, name or view as any EXR part is. Expected values: OpenEXR's bindings (each
pixel's samples) and OpenImageIO (the subimages' names and views)."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings

import numpy as np
import pytest

import lenslab.io as lio

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")


def lenslab(*args):
    return subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)


def counts(path):
    """(total, most in one pixel, pixels with samples) of each part, from OpenEXR's bindings."""
    out = []
    for part in OpenEXR.File(str(path)).parts:
        n = np.array([0 if p is None else len(p) for p in part.channels["Z"].pixels.ravel()])
        out.append((int(n.sum()), int(n.max()), int(np.count_nonzero(n))))
    return out


@pytest.fixture(scope="module")
def trunks(shared_data):
    base = shared_data / "formats" / "openexr-images" / "v2"
    return base / "LowResLeftView" / "Trunks.exr", base / "Stereo" / "Trunks.exr"


def test_info_describes_the_deep_parts(trunks):
    for path in trunks:
        done = lenslab("info", path)
        assert done.returncode == 0, done.stderr
        expected = counts(path)
        parts = [line for line in done.stdout.splitlines() if line.startswith("  part ")]
        deep = [line.strip() for line in done.stdout.splitlines() if line.startswith("    deep: ")]
        assert len(parts) == len(expected) and all("deepscanline" in line for line in parts)
        assert deep == [f"deep: {t} samples in {p} pixels, at most {m} in one pixel" for t, m, p in expected]
        assert (f"flattened from {expected[0][0]} deep samples (at most {expected[0][1]} in one pixel)"
                in done.stdout)
        js = json.loads(lenslab("info", "--json", path).stdout)[0]
        assert [(p["deep_samples"]["total"], p["deep_samples"]["max_per_pixel"], p["deep_samples"]["pixels"])
                for p in js["structure"]["parts"]] == expected
        assert js["deep"]["samples"] == expected[0][0]


def test_a_part_of_the_deep_stereo_file_by_index_name_or_view(trunks):
    path = trunks[1]
    inp = oiio.ImageInput.open(str(path))
    inp.seek_subimage(1, 0)
    name, view = inp.spec().getattribute("name"), inp.spec().getattribute("view")
    inp.close()
    assert (name, view) == ("rgba.right", "right")
    images = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a selected part: no note
        for sel in ("1", name, view):
            image, meta = lio.read(f"{path}:{sel}")
            assert meta["part"] == 1 and meta["deep"]["samples"] == counts(path)[1][0]
            images.append(image)
    np.testing.assert_array_equal(images[0], images[1])
    np.testing.assert_array_equal(images[0], images[2])
    left, _ = lio.read(f"{path}:left")
    assert not np.array_equal(left, images[0])


def test_warp_and_convert_take_a_deep_file(trunks, tmp_path):
    src = trunks[0]
    done = lenslab("convert", src, "--to", "exr", "-o", tmp_path / "c.exr")
    assert done.returncode == 0, done.stderr
    flat = OpenEXR.File(str(tmp_path / "c.exr")).parts[0]
    assert str(flat.type()).endswith("scanlineimage")
    image, _ = lio.read(src)
    again, _ = lio.read(tmp_path / "c.exr")
    # the flattened float values written as half (the samples' type): one half rounding, 2**-11 relative
    np.testing.assert_allclose(again, image, rtol=2.0 ** -11, atol=2.0 ** -24)
    warp = ["--from", "perspective:fov=90", "--to", "perspective:fov=60", "--size", "64x36"]
    for name in ("c.exr", "w.exr"):  # the flat conversion, then the deep file: one image, one warp
        done = lenslab("warp", src if name == "w.exr" else tmp_path / name, *warp, "-o", tmp_path / ("w" + name))
        assert done.returncode == 0, done.stderr
    warped, meta = lio.read(tmp_path / "ww.exr")
    assert warped.shape == (36, 64, 4) and meta["channels"] == ["R", "G", "B", "A"]
    assert 0 < warped[..., 3].max() <= 1 and np.isfinite(warped).all()
    # the same warp of inputs one half rounding apart (values <= 0.4), each output rounded to half once: 2**-11
    np.testing.assert_allclose(warped, lio.read(tmp_path / "wc.exr")[0], rtol=0, atol=2.0 ** -11)


def test_a_deep_file_lenslab_cannot_count_is_refused_in_one_line(tmp_path):
    """ZSTD-compressed deep samples (OpenEXR 3.4 writes them): their count tables cannot be read before
    OpenEXR allocates the samples, so the file is refused, naming the compression (as OpenEXR names it)."""
    chans = {n: np.empty((2, 3), dtype=object) for n in ("A", "R", "G", "B", "Z")}
    for n in chans:
        chans[n][0, 1] = np.array([0.5], np.float32 if n == "Z" else np.float16)
    path = tmp_path / "zstd.exr"
    OpenEXR.File({"compression": OpenEXR.ZSTD_COMPRESSION, "type": OpenEXR.deepscanline, "name": "beauty"},
                 chans).write(str(path))
    assert OpenEXR.File(str(path)).parts[0].header["compression"] == OpenEXR.ZSTD_COMPRESSION
    done = lenslab("info", path)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        f"lenslab info: error: {path}: part 0 ('beauty') is a deep image compressed as zstd; lenslab counts deep "
        "samples compressed as none, rle, zips, zip only, before reading them: rewrite it with one of those"]
