"""The compiled kernels' build follows ``LENSLAB_ARCH`` in a build directory that was configured before for
another CPU (``build/{wheel_tag}`` is kept between builds: a packager's ``-DLENSLAB_ARCH=x86-64-v2`` after a
developer's ``pip install -e .``). The vector maths of glibc (``LENSLAB_MVEC``, AVX2 code) may be compiled in
only where the compiler itself says the target has AVX2 (outside value: ``c++ -march=... -dM -E``, its
predefined macros). CMake is run to configure only (no compilation of the kernels)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CXX = shutil.which("c++") or shutil.which("g++")

#: the build tool CMake writes for (configuring needs one; nothing is built)
GENERATOR = "Ninja" if shutil.which("ninja") else "Unix Makefiles" if shutil.which("make") else None

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None or CXX is None or GENERATOR is None,
                                reason="cmake, a build tool and a C++ compiler build the kernels (.ci/run installs "
                                       "them)")


def _has_avx2(arch: str) -> bool:
    macros = subprocess.run([CXX, f"-march={arch}", "-dM", "-E", "-x", "c++", "-"], input="", capture_output=True,
                            text=True, check=True).stdout
    return "#define __AVX2__ 1" in macros


def _configure(build: Path, arch: str | None) -> str:
    """Configure ``build`` for ``arch`` (None: no LENSLAB_ARCH given, as a plain ``pip install -e .``); the
    compile command of the lens kernels (the ones that use libmvec), as CMake writes it down."""
    given = [] if arch is None else [f"-DLENSLAB_ARCH={arch}"]
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", GENERATOR, *given,
                    "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON", f"-DPython_EXECUTABLE={sys.executable}"],
                   check=True, capture_output=True, text=True)
    commands = json.loads((build / "compile_commands.json").read_text())
    return next(c["command"] for c in commands if c["file"].endswith("src/native/lens_tile_pixels.cpp")) + " "


def test_mvec_follows_the_target_cpu_when_the_build_directory_is_reused(tmp_path):
    if not _has_avx2("native"):
        pytest.skip("this CPU has no AVX2: the vector maths are never on here")
    build = tmp_path / "build"
    first = "LENSLAB_MVEC" in _configure(build, "native")  # (where glibc has them: 2.35 or later)
    assert not _has_avx2("x86-64")
    assert "LENSLAB_MVEC" not in _configure(build, "x86-64")  # the same directory, now for any x86-64
    assert ("LENSLAB_MVEC" in _configure(build, "native")) == first  # and back


def test_a_build_without_lenslab_arch_is_for_this_cpu_again(tmp_path):
    """``LENSLAB_ARCH`` holds for the build it is given to: a later ``pip install -e .`` (no CMAKE_ARGS) in the
    same build directory builds for the CPU it runs on, as the docs promise, not for the packager's target."""
    build = tmp_path / "build"
    assert "-march=x86-64 " in _configure(build, "x86-64")
    flags = _configure(build, None)
    assert "-march=native " in flags and "-march=x86-64 " not in flags
    assert flags.replace(str(build), "") == _configure(tmp_path / "fresh", None).replace(str(tmp_path / "fresh"), "")
