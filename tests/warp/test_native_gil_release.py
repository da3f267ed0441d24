"""Every compiled function a warp's bands call releases Python's GIL, so bands of a warp run on several threads at
once (the engine runs one band per thread: :mod:`lenslab.warp.kernels.dispatch`).

Read from the bindings' sources: each ``m.def`` of the extension's warp, map, sampler and lens bindings carries
nanobind's ``gil_scoped_release`` (as a call guard, or as a scope inside the function once its arguments are
checked). A function that does not is named here with why it may keep the GIL.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "native"
#: the binding files of everything a band can call (samplers, the map lattice, the footprint filter, lens kernels)
FILES = ("module.cpp", "bind_map.cpp", "footprint_runs.cpp", "secants.cpp", "lens_bindings.cpp", "lens_dirs.cpp")
#: functions that keep the GIL, and why
KEEPS_GIL = {"fold_piece": "one scalar look-up in the table of a cube's pieces, called by the separable filter's NumPy reference only"}


def bindings(text: str):
    """``(name, block)`` of each ``m.def(...)`` in a file: its text up to the next one (or the file's end)."""
    starts = [m.start() for m in re.finditer(r"\bm\.def\(", text)]
    for a, b in zip(starts, starts[1:] + [len(text)]):
        block = text[a:b]
        name = re.match(r'm\.def\(\s*("?)(\w+)', block)
        yield (name.group(2) if name else "?"), block


@pytest.mark.skipif(not SRC.is_dir(), reason="the C++ sources are not beside this installed copy")
@pytest.mark.parametrize("file", FILES)
def test_every_band_kernel_releases_the_gil(file):
    text = (SRC / file).read_text(encoding="utf-8")
    # lens_bindings.cpp names its call guard once: `const auto release = nb::call_guard<nb::gil_scoped_release>()`
    guard = re.search(r"const auto (\w+) = nb::call_guard<nb::gil_scoped_release>\(\)", text)
    found = list(bindings(text))
    assert found, f"no m.def in {file}"
    for name, block in found:
        if name in KEEPS_GIL:
            continue
        released = "gil_scoped_release" in block or (guard is not None and re.search(
            rf"[,(]\s*{guard.group(1)}\s*[,)]", block) is not None)
        assert released, f"{file}: {name} holds the GIL while it runs (add nb::call_guard<nb::gil_scoped_release>())"
