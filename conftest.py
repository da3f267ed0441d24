"""Doctest collection over the library (``--doctest-modules``, set in pyproject.toml).

A library module that needs an optional extra which is not installed cannot be imported, so its
examples cannot run: it is left out of the collection (and said so with ``-ra``'s summary of the
run's header), instead of failing the whole run. Any other import error still fails.
"""

from __future__ import annotations

import importlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent


def pytest_ignore_collect(collection_path, config):
    path = Path(collection_path)
    if path.suffix != ".py" or ROOT / "lenslab" not in path.parents or path.name == "__main__.py":
        return None  # pytest never imports a __main__.py for its doctests
    module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
    if module.endswith(".__init__"):
        module = module[: -len(".__init__")]
    try:
        importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and not exc.name.startswith("lenslab"):
            return True  # an optional extra that is not installed
        raise
    return None
