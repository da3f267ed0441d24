"""The layout's promises: light command start-up, and no reverse dependency from image work to the tracer."""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("numpy", "cv2", "OpenEXR", "colour", "pyvista", "vtk", "trimesh", "embreex", "matplotlib", "nlopt", "numba", "tracer")


def _modules_after(code: str) -> set[str]:
    """Top-level modules loaded by a fresh interpreter after running ``code``."""
    out = subprocess.run(
        [sys.executable, "-c", code + "\nimport sys, json; print(json.dumps(sorted({m.split('.')[0] for m in sys.modules})))"],
        check=True, capture_output=True, text=True,
    ).stdout
    return set(json.loads(out.strip().splitlines()[-1]))


def test_help_imports_nothing_heavy():
    # `lenslab --help` builds every subcommand's parser: none of them may load a numeric library.
    loaded = _modules_after("from lenslab.cli.main import build_parser; build_parser().format_help()")
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_tracer_help_imports_no_scene_library():
    loaded = _modules_after(
        "import contextlib, io\n"
        "from tracer.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n        main(['--help'])\n    except SystemExit:\n        pass"
    )
    assert not loaded & {"pyvista", "vtk", "trimesh", "embreex", "matplotlib"}, sorted(loaded)


def test_warping_and_converting_never_load_the_tracer_or_pyvista():
    loaded = _modules_after(
        "import numpy as np\n"
        "import lenslab.io, lenslab.tone, lenslab.warp\n"
        "from lenslab.lenses import Camera\n"
        "src = Camera.from_spec('equirect', (64, 32)); dst = Camera.from_spec('fisheye:fov=180', (16, 16))\n"
        "lenslab.warp.warp(np.ones((32, 64, 3), np.float32), src, dst)\n"
        "lenslab.tone.tonemap(np.ones((4, 4, 3), np.float32), curve='hable')"
    )
    assert not loaded & {"tracer", "pyvista", "vtk", "trimesh", "embreex"}, sorted(loaded)


def test_lenslab_package_never_imports_tracer_at_module_level():
    # Only the commands whose job is tracing (demo, validate) may import it, inside their functions.
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "lenslab"
    offenders = []
    for path in root.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in tree.body:  # module level only
            if isinstance(node, ast.Import) and any(a.name.split(".")[0] == "tracer" for a in node.names):
                offenders.append(str(path))
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "tracer":
                offenders.append(str(path))
    assert offenders == []
