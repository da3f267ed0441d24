"""The compiled kernels' build follows ``LENSLAB_ARCH`` in a build directory that was configured before for
another CPU (``build/{wheel_tag}`` is kept between builds: a packager's ``-DLENSLAB_ARCH=x86-64-v2`` after a
developer's ``pip install -e .``). The vector maths of glibc (``LENSLAB_MVEC``, AVX2 code) may be compiled in
only where the compiler itself says the target has AVX2 (outside value: ``c++ -march=... -dM -E``, its
predefined macros). CMake is run to configure only (no compilation of the kernels)."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CXX = shutil.which("c++") or shutil.which("g++")

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None or CXX is None or not shutil.which("ninja"),
                                reason="cmake, ninja and a C++ compiler build the kernels (.ci/run installs them)")


def _has_avx2(arch: str) -> bool:
    macros = subprocess.run([CXX, f"-march={arch}", "-dM", "-E", "-x", "c++", "-"], input="", capture_output=True,
                            text=True, check=True).stdout
    return "#define __AVX2__ 1" in macros


def _configure(build: Path, arch: str) -> str:
    """Configure ``build`` for ``arch``; the compile line of the lens kernels (the ones that use libmvec)."""
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", f"-DLENSLAB_ARCH={arch}",
                    f"-DPython_EXECUTABLE={sys.executable}"], check=True, capture_output=True, text=True)
    ninja = (build / "build.ninja").read_text()
    block = ninja[ninja.index("src/native/lens_kernels.cpp"):]
    return re.search(r"DEFINES = (.*)", block).group(1)


def test_mvec_follows_the_target_cpu_when_the_build_directory_is_reused(tmp_path):
    if not _has_avx2("native"):
        pytest.skip("this CPU has no AVX2: the vector maths are never on here")
    build = tmp_path / "build"
    first = "LENSLAB_MVEC" in _configure(build, "native")  # (where glibc has them: 2.35 or later)
    assert not _has_avx2("x86-64")
    assert "LENSLAB_MVEC" not in _configure(build, "x86-64")  # the same directory, now for any x86-64
    assert ("LENSLAB_MVEC" in _configure(build, "native")) == first  # and back
