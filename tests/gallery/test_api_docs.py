"""The front door of the library: the names ``import lenslab`` offers, their typed signatures and
numpydoc docstrings, the docstrings' Examples (run here as doctests, the numbers in them worked out by
hand), ``py.typed``, and ``write(..., alpha=)`` read back by the OpenEXR library and OpenCV."""

from __future__ import annotations

import doctest
import fnmatch
import inspect
import re
import tomllib
from importlib import resources

import cv2
import numpy as np
import OpenEXR
import pytest

import lenslab
from lenslab.errors import FormatError
from tests.conftest import REPO

FRONT = ("read", "write", "warp", "Camera", "make_lens", "tonemap")


def public_api():
    """The functions the API reference documents (docs/api.md), with their names."""
    from lenslab.lenses import Camera, Lens
    from lenslab.tone.plot import plot_curves
    from lenslab.warp import warp_with_map

    return {"read": lenslab.read, "write": lenslab.write, "warp": lenslab.warp.warp if inspect.ismodule(lenslab.warp)
            else lenslab.warp, "make_lens": lenslab.make_lens, "tonemap": lenslab.tonemap,
            "warp_with_map": warp_with_map, "plot_curves": plot_curves, "Camera": Camera,
            "Camera.from_spec": Camera.from_spec, "Lens.pixel_to_dir": Lens.pixel_to_dir,
            "Lens.dir_to_pixel": Lens.dir_to_pixel, **reference_api()}


def reference_api():
    """The rest of what docs/api.md documents: inspection, poses, tiles and filters, ST maps, the tone
    curves, the fits and the error metrics. Each has a numpydoc docstring and runnable Examples."""
    from lenslab import fit, metrics, stmap, tone
    from lenslab.io import probe, registry, split_selector
    from lenslab.lenses.core import pose
    from lenslab.metrics import diff
    from lenslab.warp import filters, maps, multiview

    named = {"sniff": registry.sniff, "probe": probe.probe, "split_selector": split_selector,
             "Pose": pose.Pose, "ypr_matrix": pose.ypr_matrix, "look_at_matrix": pose.look_at_matrix,
             "warp_tiles": multiview.warp_tiles, "sample": filters.sample, "exact_map": maps.exact_map, "compare": metrics.compare,
             "diff_images": diff.diff_images, "error_image": diff.error_image}
    named |= {n: getattr(stmap, n) for n in ("st_map", "write_st_map", "read_st_map", "warp_with_st_map")}
    named |= {n: getattr(tone, n) for n in ("clamp", "gamma", "reinhard", "reinhard_extended", "reinhard2002",
                                           "hable", "aces", "aces_hill", "agx", "pbr_neutral", "drago", "mantiuk")}
    named |= {n: getattr(fit, n) for n in ("fit_lens", "read_points", "fit_points", "fit_tone", "autoscale")}
    named |= {n: getattr(metrics, n) for n in ("valid_mask", "relative_l1", "rmse", "psnr_log", "share_off", "flip",
                                                    "noise_floor", "noise_floor_split", "edge_mask_from_aovs",
                                                    "edge_mask_from_image", "dilate")}
    named |= {n: getattr(tone, n) for n in ("auto_exposure", "curve_names", "get_curve")}
    named["error_map"] = metrics.error_map
    return named


def test_the_api_page_shows_every_documented_object():
    page = (REPO / "docs" / "api.md").read_text()
    shown = {line.split("::: ", 1)[1].strip() for line in page.splitlines() if line.startswith("::: ")}
    for name, obj in reference_api().items():
        module = obj.__module__
        assert f"{module}.{obj.__qualname__}" in shown or (module in shown and name in page), name


def test_dir_lists_the_lazily_loaded_api():
    assert set(FRONT) <= set(dir(lenslab)) and set(FRONT) <= set(lenslab.__all__)
    assert all(callable(getattr(lenslab, name)) for name in FRONT)


def test_the_packages_ship_py_typed():
    for package in ("lenslab", "tracer"):
        assert resources.files(package).joinpath("py.typed").is_file()
    # the wheel holds every file of its packages but what it excludes: py.typed is neither left out nor
    # left behind
    wheel = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["scikit-build"]["wheel"]
    assert {"lenslab", "tracer"} <= set(wheel["packages"])
    assert not any(fnmatch.fnmatch(f"{p}/py.typed", pat) for p in ("lenslab", "tracer") for pat in wheel["exclude"])


@pytest.mark.parametrize("name", sorted(public_api()))
def test_public_functions_have_typed_signatures(name):
    func = public_api()[name]
    target = func.__init__ if inspect.isclass(func) else func
    sig = inspect.signature(target)
    missing = [p.name for p in sig.parameters.values() if p.name not in ("self", "cls") and p.annotation is p.empty]
    assert not missing, f"{name}: parameters without a type: {missing}"
    assert sig.return_annotation is not sig.empty, f"{name}: no return type"


@pytest.mark.parametrize("name", sorted(public_api()))
def test_public_docstrings_are_numpydoc_and_name_every_parameter(name):
    func = public_api()[name]
    doc = inspect.getdoc(func)
    target = func.__init__ if inspect.isclass(func) else func
    params = [p.name if p.kind is not p.VAR_KEYWORD else f"**{p.name}"
              for p in inspect.signature(target).parameters.values() if p.name not in ("self", "cls")]
    if params:
        assert "\nParameters\n----------\n" in doc, name
        section = doc.split("\nParameters\n----------\n", 1)[1]
        section = re.split(r"\n[A-Z][a-z]+\n-{3,}\n", section)[0]
        documented = {n.strip() for line in section.splitlines() if line and not line.startswith(" ")
                      for n in line.split(" : ")[0].split(",")}
        assert set(params) <= documented, f"{name}: undocumented {set(params) - documented}"
    if not inspect.isclass(func) and name != "Camera.from_spec" or name in FRONT:
        assert "\nReturns\n-------\n" in doc or inspect.isclass(func), name


@pytest.mark.parametrize("name", ["lenslab", *FRONT, "warp_with_map", "plot_curves",
                                  *sorted(set(reference_api()) - {"read_st_map"})])
def test_docstring_examples_run(name):
    """The Examples sections shown in the API reference give what they print."""
    obj = lenslab if name == "lenslab" else public_api()[name]
    tests = doctest.DocTestFinder(recurse=False).find(obj, name, globs={})
    examples = sum(len(t.examples) for t in tests)
    assert examples >= 2, f"{name} has no Examples section"
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    for t in tests:
        runner.run(t)
    assert runner.failures == 0, f"{runner.failures} of the examples of {name} failed (see the output above)"


def test_write_stores_the_warps_alpha_as_the_exr_a_channel(tmp_path):
    pano = np.full((32, 64, 3), 3.0, np.float32)
    src = lenslab.Camera.from_spec("equirect", (64, 32))
    dst = lenslab.Camera.from_spec("fisheye:fov=180", (16, 16))
    image, alpha = lenslab.warp(pano, src, dst)
    path = lenslab.write(tmp_path / "fish.exr", image, alpha=alpha, pixel_type="float")
    channels = OpenEXR.File(str(path), separate_channels=True).channels()
    assert sorted(channels) == ["A", "B", "G", "R"]
    np.testing.assert_array_equal(channels["A"].pixels, alpha)
    np.testing.assert_array_equal(channels["R"].pixels, image[..., 0])
    assert alpha[0, 0] == 0 and alpha[8, 8] == 1  # the corner lies outside the image circle


def test_write_drops_alpha_where_the_format_has_none_and_refuses_a_wrong_size(tmp_path):
    colour = np.full((4, 6, 3), 0.5, np.float32)
    path = lenslab.write(tmp_path / "a.jpg", colour, alpha=np.ones((4, 6), np.float32))
    assert cv2.imread(str(path), cv2.IMREAD_UNCHANGED).shape == (4, 6, 3)
    png = cv2.imread(str(lenslab.write(tmp_path / "a.png", colour, alpha=np.full((4, 6), 0.5))), cv2.IMREAD_UNCHANGED)
    assert png.shape == (4, 6, 4) and np.all(png[..., 3] == 128)  # 0.5 * 255 rounded, alpha is not sRGB-encoded
    with pytest.raises(FormatError, match="alpha of shape"):
        lenslab.write(tmp_path / "b.exr", colour, alpha=np.ones((6, 4)))
    with pytest.raises(FormatError, match="already has 4 channels"):
        lenslab.write(tmp_path / "c.exr", np.ones((4, 6, 4), np.float32), alpha=np.ones((4, 6)))
