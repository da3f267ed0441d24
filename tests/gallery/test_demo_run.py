"""``lenslab demo`` at a tiny size: it runs, every file it claims exists and reads back, every image on its
page decodes and loads in a real headless browser, its figures match its files, and it never clobbers a
folder that holds something."""

from __future__ import annotations

import contextlib
import io
import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from gallery.browser import check_page
from gallery.items import FileList, LensView, Panorama, from_json
from lenslab import metrics
from lenslab.cli.main import main
from lenslab.io import read
from lenslab.lenses import REGISTRY
from tests.gallery.test_gallery_page import assert_page_images_decode

# A tiny run: 64x32 panorama at 1 spp, 32 px views, direct traces at 2 spp (a few seconds).
TINY = ["--size", "64x32", "--view-size", "32", "--spp", "1", "--direct-spp", "2"]


def run_demo(*args: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["demo", *args])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo") / "lenslab-demo"
    code, stdout, stderr = run_demo("-o", str(out), *TINY)
    assert code == 0, stderr
    records = [from_json(d) for d in json.loads((out / "gallery.json").read_text())["items"]]
    return out, stdout, records


def test_demo_ends_by_printing_where_the_gallery_is(demo):
    out, stdout, _ = demo
    lines = stdout.strip().splitlines()
    assert lines[-1] == f"gallery: {out / 'index.html'}"
    assert (out / "index.html").is_file()
    assert any(line.startswith("lenslab demo: the cornell box, a 64x32 panorama") for line in lines)


def test_every_file_it_claims_exists_and_reads_back(demo):
    out, stdout, records = demo
    files = next(r for r in records if isinstance(r, FileList)).files
    assert f"wrote {len(files)} image files" in stdout
    assert {f["format"] for f in files} >= {"EXR", "PFM", "PPM", "JPG"}
    for f in files:
        path = out / f["path"]
        assert path.is_file(), f["path"]
        image, meta = read(path)
        assert image.dtype == np.float32 and image.ndim == 3 and image.shape[-1] in (3, 4), f["path"]
        assert np.all(np.isfinite(image)), f["path"]
        assert meta["format"].upper() == f["format"], f["path"]  # read by its content, not its name
        assert meta["display_encoded"] == (f["format"] in ("PPM", "JPG")), f["path"]
        if f["format"] == "EXR":
            assert meta["camera"] is not None, f"{f['path']} does not carry its camera"
        if f["format"] in ("PPM", "JPG"):  # display images: decoded back to [0, 1]
            assert image.min() >= 0.0 and image.max() <= 1.0


def test_files_carry_the_cameras_and_sizes_of_their_records(demo):
    out, _, records = demo
    pano = next(r for r in records if isinstance(r, Panorama))
    image, meta = read(out / pano.path)
    assert image.shape[:2] == (32, 64)
    assert meta["camera"].lens.name == "equirect"
    np.testing.assert_allclose(meta["camera"].pose.eye, pano.eye)
    for view in (r for r in records if isinstance(r, LensView)):
        image, meta = read(out / view.warped)
        assert image.shape == (view.size[1], view.size[0], 4), view.name  # RGBA: alpha is the coverage
        assert meta["camera"].lens.name == view.spec.partition(":")[0], view.name
        # one panorama, one eye: every view is seen from the panorama's eye
        np.testing.assert_allclose(meta["camera"].pose.eye, pano.eye)


def test_every_lens_model_is_shown(demo):
    _, _, records = demo
    views = [r for r in records if isinstance(r, LensView)]
    models = {v.spec.partition(":")[0] for v in views}
    # every model that makes a lens from its defaults (a lensfun profile needs a lens named in its spec)
    from gallery.views import has_defaults

    assert models >= {m for m in REGISTRY if has_defaults(m)} - {"equirect", "distortion"}
    mappings = {v.spec for v in views if v.spec.startswith("fisheye:")}
    for m in ("equidistant", "equisolid", "stereographic", "orthographic"):
        assert any(f"mapping={m}" in s for s in mappings), m
    planet = next(v for v in views if v.name == "little planet")
    assert "stereographic" in planet.spec and planet.pose == {"pitch": -90.0}


def test_recorded_error_is_the_error_of_the_written_files(demo):
    out, _, records = demo
    compared = [r for r in records if isinstance(r, LensView) and r.direct]
    assert [c.name for c in compared] == ["fisheye, equisolid", "2x2 multi-view"]
    for view in compared:
        w, _ = read(out / view.warped)
        d, _ = read(out / view.direct)
        mask = metrics.valid_mask(d[..., 3], w[..., 3])
        l1 = metrics.relative_l1(d[..., :3], w[..., :3], mask)
        # the files are half floats (relative rounding 2^-11 per value), which moves a relative L1 by
        # at most about 2^-11 * (sum|t| + sum|r|) / sum|r|, i.e. ~1e-3
        assert l1 == pytest.approx(view.error["l1"], abs=2e-3), view.name
        assert view.trace_seconds > 0 and view.warp_seconds > 0 and view.trace_spp == 2
        assert 0 <= view.error["noise_l1"] and view.error["excess_l1"] >= 0


def test_every_page_image_exists_and_decodes(demo):
    out, _, records = demo
    page = assert_page_images_decode(out / "index.html")
    views = [r for r in records if isinstance(r, LensView)]
    compared = [v for v in views if v.direct]
    # panorama + 3 per comparison + one tile per view + one per tone curve + the curve plot
    tone = next(r for r in records if r.kind == "tone")
    assert len(page.images) == 1 + 3 * len(compared) + len(views) + len(tone.curves) + 1


@pytest.mark.slow
def test_page_loads_in_headless_chromium(demo):
    out, _, _ = demo
    shot = out / "screenshot.png"
    problems = check_page(out / "index.html", shot)
    assert problems == []
    im = cv2.imread(str(shot))
    assert im is not None and im.shape[:2] == (2000, 1200)
    assert im.std() > 10  # a page with pictures, not a blank screen


def test_refuses_a_folder_that_holds_something(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    code, stdout, stderr = run_demo("-o", str(out), *TINY)
    assert code == 1
    assert "is not empty" in stderr and "--overwrite" in stderr
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]  # nothing written
    code, stdout, stderr = run_demo("-o", str(out), *TINY, "--overwrite", "--quiet")
    assert code == 0, stderr
    assert (out / "notes.txt").read_text() == "keep me"  # other files are left alone
    assert stdout.strip() == f"gallery: {out / 'index.html'}"  # --quiet: the gallery path only
    assert not [p for p in out.rglob(".*tmp*")], "a temporary file was left behind"


def test_bad_options_are_refused():
    for args in (["--size", "100x100"], ["--size", "big"], ["--view-size", "0"], ["--quality", "best"]):
        with contextlib.redirect_stderr(io.StringIO()), pytest.raises(SystemExit) as exc:
            main(["demo", *args])
        assert exc.value.code == 2, args
    code, _, stderr = run_demo("-o", "unused", "--hdri", "/nonexistent/folder")
    assert code == 1 and "no such folder" in stderr
    assert not Path("unused").exists()


def test_command_module_imports_only_the_standard_library():
    code = ("import sys, gallery.demo as d; heavy = [m for m in ('numpy', 'cv2', 'tracer', 'gallery.build', "
            "'matplotlib', 'OpenEXR') if m in sys.modules]; print(heavy)")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert res.stdout.strip() == "[]"
