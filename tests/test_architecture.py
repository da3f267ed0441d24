"""The layout's promises: light command start-up, no reverse dependency from image work to the tracer, no
import cycle between modules or between packages, and the command line as the top layer."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

HEAVY = ("numpy", "cv2", "OpenEXR", "colour", "pyvista", "vtk", "trimesh", "embreex", "matplotlib", "nlopt", "numba")
ROOT = Path(__file__).resolve().parents[1]


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


def _imports(path: Path) -> list[str]:
    """Every module named by an import statement of ``path``, at module level or inside a function."""
    names = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.append(node.module)
    return names


def test_lenslab_never_imports_the_tracer_or_the_gallery():
    # The layers: image work (lenslab) <- tracer <- gallery. The commands that need the tracer come in
    # through the lenslab.commands entry-point group, so not even a function of lenslab imports them.
    offenders = [f"{path.relative_to(ROOT)}: {name}" for path in sorted((ROOT / "lenslab").rglob("*.py"))
                 for name in _imports(path) if name.split(".")[0] in ("tracer", "gallery")]
    assert offenders == []


def test_the_tracer_never_imports_the_gallery():
    offenders = [f"{path.relative_to(ROOT)}: {name}" for path in sorted((ROOT / "tracer").rglob("*.py"))
                 for name in _imports(path) if name.split(".")[0] == "gallery"]
    assert offenders == []


@pytest.mark.parametrize("packages", [("lenslab",), ("gallery",), ("tracer",)])
def test_no_import_cycle_between_modules(packages):
    # A module graph of the package (every import statement, including those inside functions, since
    # a cycle there is still two modules that cannot be understood apart).
    modules = {}
    for pkg in packages:
        for path in (ROOT / pkg).rglob("*.py"):
            rel = path.relative_to(ROOT).with_suffix("")
            name = ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)
            modules[name] = path
    graph = {}
    for name, path in modules.items():
        deps = set()
        for imp in _imports(path):
            while imp and imp not in modules:  # "from pkg.mod import name" -> pkg.mod
                imp = imp.rpartition(".")[0]
            # a package's __init__ importing its own submodules is how a package is made, not a cycle
            if imp and imp != name and not imp.startswith(name + "."):
                deps.add(imp)
        graph[name] = deps
    cycles = _cycles(graph)
    assert cycles == [], [" -> ".join(c) for c in cycles]


def _package_graph() -> dict[str, set[str]]:
    """Each package of lenslab (``lenslab.io``, ``lenslab.jobs``, ...; a module directly under ``lenslab``
    is its own node) -> the packages its modules import, inside functions too."""
    graph: dict[str, set[str]] = {}
    for path in (ROOT / "lenslab").rglob("*.py"):
        rel = path.relative_to(ROOT).with_suffix("").parts
        if len(rel) == 2 and rel[1] in ("__init__", "__main__"):
            continue  # the package itself and its entry point sit above every layer
        node = ".".join(rel[:2])
        deps = graph.setdefault(node, set())
        for imp in _imports(path):
            parts = imp.split(".")
            if parts[0] == "lenslab" and len(parts) > 1 and ".".join(parts[:2]) != node:
                deps.add(".".join(parts[:2]))
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = 1
        stack.append(node)
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                cycles.append(stack[stack.index(dep):] + [dep])
            elif dep not in state:
                visit(dep, stack)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
    return cycles


def test_no_import_cycle_between_packages():
    # cli <-> cluster, cli <-> bench and io <-> lenses were such cycles: two packages that cannot be
    # understood (or tested, or moved) apart. Imports inside functions count.
    graph = _package_graph()
    assert {"lenslab.cli", "lenslab.jobs", "lenslab.io", "lenslab.lenses", "lenslab.cluster"} <= set(graph)
    assert [" -> ".join(c) for c in _cycles(graph)] == []


def test_the_package_graph_finds_a_cycle_made_inside_functions():
    # the check itself: a cycle through an import inside a function is one
    assert _cycles({"a": {"b"}, "b": {"a"}}) == [["a", "b", "a"]]
    assert _imports_of("def f():\n    from lenslab.cli.main import main\n") == ["lenslab.cli.main"]


def _imports_of(code: str) -> list[str]:
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "m.py"
        path.write_text(code)
        return _imports(path)


def test_nothing_outside_the_command_line_imports_it():
    # lenslab.cli turns arguments into jobs and prints; the library, the cluster, the benchmarks, the tracer
    # and the gallery use lenslab.jobs (and lenslab.jobs.arguments, lenslab.jobs.funnel for their own
    # commands). Only `python -m lenslab` starts it.
    offenders = [f"{path.relative_to(ROOT)}: {name}"
                 for pkg in ("lenslab", "tracer", "gallery") for path in sorted((ROOT / pkg).rglob("*.py"))
                 if (ROOT / "lenslab" / "cli") not in path.parents and path != ROOT / "lenslab" / "__main__.py"
                 for name in _imports(path) if name == "lenslab.cli" or name.startswith("lenslab.cli.")]
    assert offenders == []


def test_demo_and_validate_come_from_the_entry_point_group():
    from importlib.metadata import entry_points

    from lenslab.cli.main import COMMANDS, build_parser

    group = {ep.name: ep.value for ep in entry_points(group="lenslab.commands")}
    assert group == {"demo": "gallery.demo", "validate": "tracer.validate.command"}
    assert not {"demo", "validate"} & set(COMMANDS)
    help_text = build_parser().format_help()
    assert "demo" in help_text and "validate" in help_text
