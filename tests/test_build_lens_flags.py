"""Every source file of the lens kernels is built with the same flags, multiplies and adds unfused
(``-ffp-contract=off``), so each kernel rounds as its NumPy reference does, whichever file it lives in. The outside
value is CMake's own record of each compile command (``compile_commands.json``); CMake configures only (nothing is
compiled)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NATIVE = ROOT / "src" / "native"
GENERATOR = "Ninja" if shutil.which("ninja") else "Unix Makefiles" if shutil.which("make") else None

#: the lens sources that hold no kernel: the Python bindings (nanobind's argument conversion)
NOT_KERNELS = {"lens_bindings.cpp"}

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None or GENERATOR is None
                                or (shutil.which("c++") or shutil.which("g++")) is None,
                                reason="cmake, a build tool and a C++ compiler build the kernels (.ci/run installs "
                                       "them)")


def test_every_lens_kernel_file_is_built_unfused_with_the_same_flags(tmp_path):
    build = tmp_path / "build"
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", GENERATOR, "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                    f"-DPython_EXECUTABLE={sys.executable}"], check=True, capture_output=True, text=True)
    commands = {Path(c["file"]).name: c["command"] for c in json.loads((build / "compile_commands.json").read_text())}
    kernels = sorted(p.name for p in NATIVE.glob("lens_*.cpp") if p.name not in NOT_KERNELS)
    assert len(kernels) >= 6 and all(name in commands for name in kernels)  # every one is part of the module

    def flags(name: str) -> str:
        # the command without its file names (the source and the object it writes)
        cmd = commands[name].replace(str(build), "BUILD")
        return re.sub(r"\S*" + re.escape(Path(name).stem) + r"\S*", "FILE", cmd)

    for name in kernels:
        assert re.findall(r"-ffp-contract=(\w+)", commands[name])[-1] == "off", name  # the last one given wins
    assert len({flags(name) for name in kernels}) == 1
    assert re.findall(r"-ffp-contract=(\w+)", commands["lens_bindings.cpp"])[-1] == "fast"  # the rest of the module
