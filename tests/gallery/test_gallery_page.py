"""The gallery page built from stand-in images: every image it links exists and decodes, every card's text
is its function's docstring, the difference map measures what the card's figure says, and the page
rebuilds from its records."""

from __future__ import annotations

import html
import inspect
import json
from html.parser import HTMLParser
from pathlib import Path

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gallery import cards
from gallery.browser import check_page, find_chromium
from gallery.build import build_gallery, load_manifest
from gallery.page import card_text
from gallery.display import difference
from gallery.errors import GalleryError
from gallery.items import Display, FileList, LensView, Panorama, RunInfo, ToneSet, from_json, to_json
from lenslab import metrics
from lenslab.io import read, write


class PageImages(HTMLParser):
    """Collects ``<img>`` tags (src, width, height) and ``<a href>`` targets of a page."""

    def __init__(self):
        super().__init__()
        self.images: list[dict] = []
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a)
        elif tag == "a" and a.get("href") and not a["href"].startswith("#"):
            self.links.append(a["href"])


def parse_page(index: Path) -> PageImages:
    p = PageImages()
    p.feed(index.read_text(encoding="utf-8"))
    return p


def assert_page_images_decode(index: Path) -> PageImages:
    """Every <img> of the page is a relative link to a file that OpenCV decodes, at the size the tag states."""
    page = parse_page(index)
    assert page.images, "the page shows no image"
    for tag in page.images:
        src = tag["src"]
        assert not Path(src).is_absolute() and "://" not in src, f"{src}: links must be relative"
        path = index.parent / src
        assert path.is_file(), f"{src} is referenced by the page but missing"
        decoded = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        assert decoded is not None, f"{src} does not decode"
        assert (int(tag["width"]), int(tag["height"])) == (decoded.shape[1], decoded.shape[0]), src
    for href in page.links:
        assert (index.parent / href).is_file(), f"link {href} points at no file"
    return page


def _scene(h: int, w: int, seed: int = 0) -> np.ndarray:
    """A smooth HDR gradient with a small bright spot (a stand-in render), float32 H x W x 3."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    img = np.stack([x / w, y / h, 0.5 + 0.25 * np.sin(x / 5.0)], axis=-1) * np.float32(0.8)
    img[h // 3: h // 3 + 3, w // 2: w // 2 + 3] = 40.0
    rng = np.random.default_rng(seed)
    return (img * (1 + 0.02 * rng.standard_normal(img.shape))).astype(np.float32)


def _disc_alpha(n: int) -> np.ndarray:
    y, x = np.mgrid[0:n, 0:n] + 0.5
    return (np.hypot(x - n / 2, y - n / 2) <= n / 2).astype(np.float32)


def stand_in_records(out: Path) -> list:
    """Stand-in HDR files in ``out`` and the records that point at them."""
    (out / "hdr").mkdir(parents=True)
    write(out / "hdr" / "pano.exr", _scene(32, 64), pixel_type="float")
    a = _disc_alpha(40)
    warped = np.concatenate([_scene(40, 40, 1) * a[..., None], a[..., None]], axis=-1)
    direct = np.concatenate([_scene(40, 40, 2) * a[..., None], a[..., None]], axis=-1)
    write(out / "hdr" / "warped.exr", warped, pixel_type="float")
    write(out / "hdr" / "direct.exr", direct, pixel_type="float")
    write(out / "hdr" / "other.exr", _scene(24, 36, 3), pixel_type="float")
    return [
        Display(curve="hable", exposure=0.5),
        Panorama(path="hdr/pano.exr", spec="equirect", size=(64, 32), scene="stand-in", spp=4, seconds=1.5,
                 eye=(0.1, 0.2, 0.3), integrator="path", max_depth=8),
        LensView(name="fisheye, equisolid", spec="fisheye:fov=180,mapping=equisolid", size=(40, 40),
                 warped="hdr/warped.exr", warp_seconds=0.01, settings={"filter": "bilinear", "antialias": True},
                 direct="hdr/direct.exr", trace_seconds=2.0, trace_spp=16,
                 error={"l1": 0.03, "noise_l1": 0.02, "excess_l1": 0.01, "psnr_log": 40.0}),
        LensView(name="swirl <&> \"quoted\"", spec="swirl:amount=6", size=(36, 24), warped="hdr/other.exr",
                 warp_seconds=0.002, pose={"pitch": -90.0}, note="a note with <markup>"),
        ToneSet(source="hdr/warped.exr", curves=["clamp", "reinhard", "hable"], exposure=0.5, label="stand-in"),
        FileList(files=[{"path": "hdr/pano.exr", "format": "EXR", "what": "panorama"}]),
        RunInfo(command="stand-in", seconds=3.0, settings={"quality": "test"}),
    ]


def validation_report(folder: Path) -> Path:
    """A report folder shaped like the one ``lenslab validate`` writes (results.json with rows)."""
    folder.mkdir(parents=True)
    rows = []
    for i, (size, seconds, l1) in enumerate([((256, 128), 0.5, 0.04), ((512, 256), 1.0, 0.02),
                                             ((512, 256), 1.4, 0.025), ((1024, 512), 3.0, 0.012)]):
        rows.append({"kind": "warp", "label": f"{size[0]}x{size[1]} s{i}", "pano_size": list(size), "seconds": seconds,
                     "l1": l1, "l1_interior": l1 * 0.7, "noise_l1": 0.005})
    rows.append({"kind": "direct", "label": "direct 16 spp", "pano_size": None, "seconds": 2.0, "l1": 0.03,
                 "l1_interior": 0.028, "noise_l1": 0.005})
    pareto = ["256x128 s0", "512x256 s1", "1024x512 s3"]
    data = {"meta": {"target": "fisheye:fov=180", "size": [64, 64], "mode": "monte-carlo",
                     "reference": {"noise_l1": 0.005}}, "rows": rows, "pareto": pareto}
    (folder / "results.json").write_text(json.dumps(data), encoding="utf-8")
    return folder


def hdri_folder(folder: Path) -> Path:
    """Two small equirect panoramas (EXR and PFM), an image that is not a panorama, a broken EXR and a text file."""
    folder.mkdir(parents=True)
    write(folder / "a.exr", _scene(32, 64, 5), pixel_type="float")
    write(folder / "b.pfm", _scene(16, 32, 6))
    write(folder / "not-a-panorama.exr", _scene(20, 30, 7))
    (folder / "broken.exr").write_bytes(b"v/1\x01 not really an EXR")
    (folder / "notes.txt").write_text("not an image")
    return folder


@pytest.fixture(scope="module")
def stand_in(tmp_path_factory) -> tuple[Path, list]:
    out = tmp_path_factory.mktemp("gallery")
    records = stand_in_records(out)
    report = validation_report(tmp_path_factory.mktemp("report") / "report")
    hdri = hdri_folder(tmp_path_factory.mktemp("hdri") / "hdri")
    index = build_gallery(out, *records, validate_report=report, hdri_dir=hdri, title="stand-in <gallery>")
    return index, records


def test_every_page_image_exists_and_decodes(stand_in):
    index, _ = stand_in
    assert index.name == "index.html"
    page = assert_page_images_decode(index)
    srcs = [t["src"] for t in page.images]
    assert len(srcs) == len(set(srcs)), "two cards wrote the same image file"
    # panorama 1 + comparison 3 + two lens views + three tone curves + curve plot + validation plot
    # + per usable panorama of the HDRI folder its thumbnail and two warped views
    assert len(srcs) == 1 + 3 + 2 + 3 + 1 + 1 + 2 * 3
    assert (index.parent / "style.css").is_file()


def test_card_text_is_the_card_functions_docstring(stand_in):
    index, _ = stand_in
    text = index.read_text(encoding="utf-8")
    for name in ("panorama", "lens_comparisons", "lens_views", "tone_strip", "tone_curves", "validation", "files",
                 "hdri"):
        func = getattr(cards, name)
        assert inspect.getdoc(func), f"card {name} has no text"
        assert card_text(func) in text, f"the text of card {name} is not on the page"


def test_page_escapes_names_and_shows_measured_figures(stand_in):
    index, _ = stand_in
    text = index.read_text(encoding="utf-8")
    assert "<markup>" not in text and html.escape("a note with <markup>") in text
    assert html.escape('swirl <&> "quoted"') in text
    assert "<title>stand-in &lt;gallery&gt;</title>" in text
    assert "3.00%" in text and "2.00%" in text  # the record's relative L1 and noise, as percentages


def test_difference_map_mean_is_the_relative_l1(stand_in):
    index, records = stand_in
    out = index.parent
    view = next(r for r in records if isinstance(r, LensView) and r.direct)
    w, _ = read(out / view.warped)
    d, _ = read(out / view.direct)
    dmap, valid, mean = difference(w, d)
    expected = metrics.relative_l1(d[..., :3], w[..., :3], metrics.valid_mask(d[..., 3], w[..., 3]))
    # float32 maps summed in float64: agreement to ~1e-6 relative
    assert mean == pytest.approx(expected, rel=1e-5)
    assert not valid[0, 0] and valid[20, 20]  # the disc's corner is outside, its centre inside


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 0.5))
def test_difference_mean_equals_relative_l1_for_random_images(seed, hole):
    rng = np.random.default_rng(seed)
    ref = rng.random((9, 11, 3)).astype(np.float32) + 0.01
    test = (ref * (1 + 0.3 * rng.standard_normal(ref.shape))).astype(np.float32)
    alpha = (rng.random((9, 11)) >= hole).astype(np.float32)
    alpha[0, 0] = 1.0
    refa = np.concatenate([ref, alpha[..., None]], -1)
    _, valid, mean = difference(test, refa)
    assert np.array_equal(valid, alpha >= 0.999)
    # the map's normalisation makes its mean the aggregate relative L1 (float32 rounding: 1e-5)
    assert mean == pytest.approx(metrics.relative_l1(ref, test, valid), rel=1e-5)


def test_records_round_trip_through_json():
    items = [Display(), Panorama(path="p.exr", spec="equirect", size=(8, 4), eye=(1.0, 2.0, 3.0)),
             LensView(name="a", spec="fisheye", size=(4, 4), warped="a.exr", error={"l1": 0.1}),
             ToneSet(source="a.exr", curves=["hable"]), FileList(files=[{"path": "a.exr"}]), RunInfo(seconds=1.0)]
    for item in items:
        again = from_json(json.loads(json.dumps(to_json(item))))
        assert again == item
    with pytest.raises(GalleryError, match="unknown kind"):
        from_json({"kind": "nonsense"})


def test_rebuild_from_the_stored_records(stand_in, tmp_path):
    index, records = stand_in
    stored = load_manifest(index.parent)
    assert stored["items"] == records
    assert stored["title"] == "stand-in <gallery>"
    from gallery.__main__ import main

    before = index.read_bytes()
    assert main([str(index.parent), "--quiet"]) == 1  # the page exists: replaced only with --overwrite
    assert index.read_bytes() == before
    assert main([str(index.parent), "--quiet", "--overwrite"]) == 0
    assert_page_images_decode(index)
    # an empty folder with nothing to show is refused with exit code 2
    assert main([str(tmp_path / "empty"), "--quiet"]) == 2


def test_hdri_card_warps_each_panorama_and_names_the_skipped(stand_in):
    index, _ = stand_in
    page = parse_page(index)
    hdri = [t["src"] for t in page.images if Path(t["src"]).name.startswith("hdri-")]
    assert sorted(Path(s).stem for s in hdri) == ["hdri-a", "hdri-a-little-planet", "hdri-a-sky-dome",
                                                  "hdri-b", "hdri-b-little-planet", "hdri-b-sky-dome"]
    for src in hdri:
        if src.endswith(("sky-dome.jpg", "little-planet.jpg")):
            assert cv2.imread(str(index.parent / src)).shape[:2] == (256, 256)
    text = index.read_text(encoding="utf-8")
    assert "not-a-panorama.exr (30x20" in text
    assert "broken.exr (" in text  # an unreadable file is named with its reason, and the page still builds


def test_hdri_card_on_the_real_panoramas(shared_data, tmp_path):
    folder = tmp_path / "hdri"
    folder.mkdir()
    for name in ("forest.exr", "night.exr"):  # a sun of ~34000 and a dark sky
        (folder / name).write_bytes((shared_data / "hdri" / name).read_bytes())
    index = build_gallery(tmp_path / "out", hdri_dir=folder)
    page = assert_page_images_decode(index)
    assert len(page.images) == 2 * 3
    for tag in page.images:  # auto exposure: no view comes out black or burnt white
        im = cv2.imread(str(index.parent / tag["src"]))
        assert 10 < im.mean() < 245, tag["src"]


def test_bad_inputs_give_clear_errors(tmp_path):
    with pytest.raises(GalleryError, match="does not exist"):
        build_gallery(tmp_path / "a", Panorama(path="missing.exr", spec="equirect", size=(8, 4)))
    (tmp_path / "empty-report").mkdir()
    with pytest.raises(GalleryError, match="results.json"):
        build_gallery(tmp_path / "b", validate_report=tmp_path / "empty-report")
    (tmp_path / "no-hdri").mkdir()
    with pytest.raises(GalleryError, match="no panorama"):
        build_gallery(tmp_path / "c", hdri_dir=tmp_path / "no-hdri")
    with pytest.raises(GalleryError, match="not a directory"):
        build_gallery(tmp_path / "d", hdri_dir=tmp_path / "nowhere")


@pytest.mark.slow
def test_stand_in_page_loads_in_headless_chromium(stand_in):
    index, _ = stand_in
    shot = index.parent / "screenshot.png"
    assert check_page(index, shot) == []
    im = cv2.imread(str(shot))
    assert im is not None and im.shape[:2] == (2000, 1200)


def test_missing_browser_is_an_error_not_a_skip(monkeypatch, tmp_path):
    monkeypatch.delenv("LENSLAB_CHROMIUM", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))  # a PATH with no browser on it
    with pytest.raises(GalleryError, match="no Chromium browser found"):
        find_chromium()


def test_readme_montages_stay_under_their_byte_budget(stand_in, tmp_path):
    from gallery.montage import MAX_BYTES, readme_images

    index, _ = stand_in
    written = readme_images(index.parent, tmp_path / "images")
    assert [p.name for p in written] == ["panorama.jpg", "lenses.jpg", "compare.jpg", "tones.jpg", "hdri.jpg"]
    for p in written:
        assert p.stat().st_size <= MAX_BYTES, p.name
        assert cv2.imread(str(p)) is not None, p.name


@pytest.mark.slow
def test_validation_card_reads_a_real_validate_report(tmp_path):
    import contextlib
    import io

    from lenslab.cli.main import main as lenslab_main

    report = tmp_path / "report"
    args = ["validate", "--scene", "analytic", "--to", "fisheye:fov=180", "--size", "32x32", "--pano-sizes",
            "64x32,128x64", "--filters", "bilinear,antialias", "--no-flip", "--repeat", "1", "-o", str(report), "-q"]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert lenslab_main(args) == 0
    index = build_gallery(tmp_path / "out", validate_report=report)
    page = assert_page_images_decode(index)
    assert [Path(t["src"]).name for t in page.images] == ["validation-report.png"]
    pareto = json.loads((report / "results.json").read_text())["pareto"]
    text = index.read_text(encoding="utf-8")
    assert pareto and all(f"<td>{html.escape(label)}</td>" in text for label in pareto)
