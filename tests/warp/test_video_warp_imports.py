"""What ``lenslab warp clip.mp4 -o fish.mp4`` loads: the lens models it names and no other, and none of the heavy
libraries a video warp does not use (the JIT, SciPy, colour-science, OpenCV, Dask, the tone curves). Checked in a
fresh interpreter, by what ``sys.modules`` holds after the command; the model modules a full listing loads are
counted from the package's own files, and the clip is made by PyAV."""

from __future__ import annotations

import json
import pkgutil
import subprocess
import sys
from fractions import Fraction

import numpy as np
import pytest

av = pytest.importorskip("av")

import lenslab.lenses as lens_package  # noqa: E402

#: libraries (and lenslab's own packages) the video warp has no use for
HEAVY = ("numba", "llvmlite", "scipy", "colour", "cv2", "dask", "distributed", "OpenImageIO", "pyvista", "nlopt",
         "lenslab.tone", "lenslab.fit", "lenslab.lenses.lensfun.database", "lenslab.warp.pyramid_levels")


def _clip(path, w=128, h=64, frames=3, codec="libx264", first=60, step=40):
    """A clip of flat grey frames ``first``, ``first + step``, ... (8-bit codes), encoded by PyAV."""
    with av.open(str(path), "w") as c:
        s = c.add_stream(codec, rate=Fraction(24))
        s.width, s.height, s.pix_fmt = w, h, "yuv420p"
        for i in range(frames):
            f = av.VideoFrame.from_ndarray(np.full((h, w, 3), step * i + first, np.uint8), format="rgb24")
            f = f.reformat(format="yuv420p")
            f.pts = i
            for p in s.encode(f):
                c.mux(p)
        for p in s.encode():
            c.mux(p)


def _model_modules() -> set[str]:
    """Every module of lenslab.lenses that registers a model (``@register`` in its text), from its files."""
    import importlib.util

    names = set()
    for info in pkgutil.walk_packages(lens_package.__path__, lens_package.__name__ + "."):
        if not info.ispkg:
            with open(importlib.util.find_spec(info.name).origin, encoding="utf-8") as f:
                if "\n@register" in f.read():
                    names.add(info.name)
    return names


def test_a_video_warp_loads_only_the_lenses_it_names(tmp_path):
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    argv = ["warp", str(clip), "-o", str(tmp_path / "fish.mp4"), "--to", "fisheye:fov=180", "--from", "equirect",
            "--size", "64x64", "-q"]
    code = ("import json, sys\n"
            "from lenslab.cli.main import main\n"
            f"status = main({argv!r})\n"
            "print(json.dumps([status, sorted(sys.modules)]))")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    status, loaded = json.loads(out.strip().splitlines()[-1])
    assert status == 0 and (tmp_path / "fish.mp4").stat().st_size > 0
    models = _model_modules()
    assert len(models) > 20  # the package holds the models the full listing loads
    assert sorted(m for m in loaded if m in models) == ["lenslab.lenses.projections.equirect",
                                                        "lenslab.lenses.projections.fisheye"]
    assert [m for m in loaded if m.split(".")[0] in HEAVY or m in HEAVY or m.startswith(HEAVY[-4:])] == []


def test_the_registry_still_lists_every_model_after_a_lookup():
    """A lookup loads one module; listing the models afterwards loads them all, in the modules' order (the
    same list as a listing made first), so --help, the docs and the tests see every model."""
    code = ("import json\n"
            "from lenslab.lenses.registry import REGISTRY, make_lens\n"
            "first = {}\n"
            "make_lens('fisheye:fov=180', (64, 64))\n"
            "import sys\n"
            "few = sorted(m for m in sys.modules if m.startswith('lenslab.lenses.') and m.count('.') == 3)\n"
            "print(json.dumps([few, REGISTRY.names()]))")
    listed = "import json\nfrom lenslab.lenses.registry import REGISTRY\nprint(json.dumps(REGISTRY.names()))"
    run = lambda c: json.loads(subprocess.run([sys.executable, "-c", c], check=True, capture_output=True,  # noqa: E731
                                              text=True).stdout.strip().splitlines()[-1])
    few, after_lookup = run(code)
    assert [m for m in few if m.rsplit(".", 1)[0].endswith(("projections", "panoramas", "calibrated", "distortion",
                                                            "multiview", "lensfun"))] == \
        ["lenslab.lenses.projections.fisheye"]
    assert after_lookup == run(listed)
    assert {"fisheye", "equirect", "mercator", "little-planet", "opencv-fisheye", "barrel"} <= set(after_lookup)
