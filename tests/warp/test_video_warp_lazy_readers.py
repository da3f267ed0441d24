"""What a clip's warp into a model lens no longer loads before its first frame: the readers of lenses named by a
file's metadata (``--from exif``, ``--from auto``) and the footprint prefilter of ``--antialias``. Read from a fresh
interpreter's ``sys.modules`` after the command; the clip is made by PyAV. The same specs still load them."""

from __future__ import annotations

import re

import pytest

pytest.importorskip("av")

from tests.warp.test_video_startup import _loaded_after  # noqa: E402
from tests.warp.test_video_warp_imports import _clip  # noqa: E402

#: the modules a warp from equirect into a fisheye has no use for
UNUSED = ("lenslab.lenses.exif_view", "lenslab.lenses.lensfun.exif", "lenslab.warp.antialias", "lenslab.warp.pyramid")


def test_a_clip_warp_into_a_model_lens_loads_no_metadata_reader_nor_the_prefilter(tmp_path):
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    status, loaded, _ = _loaded_after(["warp", str(clip), "-o", str(tmp_path / "fish.mp4"), "--to",
                                       "fisheye:fov=180", "--from", "equirect", "--size", "64x64", "-q"])
    assert status == 0 and (tmp_path / "fish.mp4").stat().st_size > 0
    assert "lenslab.warp.taps" in loaded and "lenslab.io.video.clips" in loaded  # the warp did run here
    assert [m for m in UNUSED if m in loaded] == []


def test_an_antialiased_clip_warp_loads_the_prefilter(tmp_path):
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    status, loaded, _ = _loaded_after(["warp", str(clip), "-o", str(tmp_path / "fish.mp4"), "--to",
                                       "fisheye:fov=180", "--from", "equirect", "--size", "64x64", "-q",
                                       "--antialias"])
    assert status == 0 and (tmp_path / "fish.mp4").stat().st_size > 0
    assert "lenslab.warp.antialias" in loaded and "lenslab.warp.pyramid" in loaded


@pytest.mark.parametrize("spec, exif, auto", [
    ("exif", True, False), (" EXIF : photo=a.jpg", True, False), ("exifx", False, False),
    ("auto", False, True), ("lensfun:auto, crop=1.5", False, True), ("Auto ", False, True),
    ("fisheye:fov=180", False, False), ("equirect", False, False), ("lensfun:canon", False, False)])
def test_spec_kinds_tell_metadata_lenses_apart_as_the_readers_do(spec, exif, auto):
    """The written rule (``exif`` or ``exif:...``; ``auto`` or ``lensfun:auto`` with values after a comma,
    any case, spaces around), transcribed here, against the light module and the readers' own names."""
    from lenslab.lenses.exif_view import is_exif as reader_is_exif
    from lenslab.lenses.lensfun.exif import is_auto as reader_is_auto
    from lenslab.lenses.spec_kinds import is_auto, is_exif

    assert bool(re.fullmatch(r"\s*exif\s*(:.*)?", spec, re.S | re.I)) is exif
    assert is_exif(spec) is reader_is_exif(spec) is exif
    assert is_auto(spec) is reader_is_auto(spec) is auto


def test_a_clip_warp_loads_neither_json_nor_the_import_abcs_nor_futures(tmp_path):
    """The plan cache keys its geometries without JSON's encoder and shares a build without ``concurrent.futures``,
    and the finder of the lens modules' old names needs no ``importlib.abc`` (checked without the other tests' JSON
    reporting)."""
    import subprocess
    import sys

    clip = tmp_path / "clip.mp4"
    _clip(clip)
    argv = ["warp", str(clip), "-o", str(tmp_path / "fish.mp4"), "--to", "fisheye:fov=180", "--from", "equirect",
            "--size", "64x64", "-q"]
    code = (f"import sys\nfrom lenslab.cli.main import main\nstatus = main({argv!r})\n"
            "print(status, [m for m in ('json', 'importlib.abc', 'concurrent.futures') if m in sys.modules])")
    done = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    assert done.stdout.strip().splitlines()[-1] == "0 []"


@pytest.mark.parametrize("other", ["fisheye:fov=180.0000001", "fisheye:fov=180,mapping=equisolid", "fisheye:fov=170"])
def test_the_plan_key_tells_geometries_apart_as_their_json_descriptions_do(other):
    """The key's equality against the cameras' JSON descriptions with sorted keys (the plan cache's earlier key,
    transcribed here): equal for cameras made twice, different for another lens, size or pose."""
    import json

    from lenslab.lenses import Camera
    from lenslab.warp.batch import geometry_key

    def described(a, b):
        return json.dumps([a.to_dict(), b.to_dict()], sort_keys=True, default=str)

    src = Camera.from_spec("equirect", (64, 32))
    cams = [Camera.from_spec("fisheye:fov=180", (32, 32)), Camera.from_spec("fisheye:fov=180", (32, 32)),
            Camera.from_spec(other, (32, 32)), Camera.from_spec("fisheye:fov=180", (32, 30)),
            Camera.from_spec("fisheye:fov=180", (32, 32), yaw=1e-9)]
    for a in cams:
        for b in cams:
            assert (geometry_key(src, a) == geometry_key(src, b)) is (described(src, a) == described(src, b))
    assert len({geometry_key(src, c) for c in cams}) == 4
