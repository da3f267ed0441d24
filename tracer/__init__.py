"""tracer: a compact reference ray tracer for lenslab cameras (pyvista scenes, embree ray casts).

``tracer.load_scene("cornell")`` (or a path to an OBJ, PLY, STL or TOML scene) gives a :class:`Scene`;
``tracer.render(scene, camera, spp=64, seed=0, integrator="path", max_depth=8)`` traces it through
any :class:`lenslab.lenses.Camera` and returns a :class:`RenderResult` (image, per-pixel variance of the
mean, alpha, spp, seconds). For noise-free references, render ``cornell-point`` (or any scene lit by
point lights) with ``integrator="direct"`` and ``seed=None`` (samples at the strata centres).
Importing this package is cheap: the modules load on first use.
"""

from __future__ import annotations

import importlib

_LAZY = {
    "render": ("tracer.rendering", "render"),
    "RenderResult": ("tracer.rendering", "RenderResult"),
    "relative_error": ("tracer.rendering", "relative_error"),
    "load_scene": ("tracer.load", "load_scene"),
    "Scene": ("tracer.scene", "Scene"),
    "SceneError": ("tracer.scene", "SceneError"),
    "Material": ("tracer.materials", "Material"),
    "PointLight": ("tracer.scene", "PointLight"),
    "trace": ("tracer.integrators", "trace"),
    "trace_pixels": ("tracer.rendering", "trace_pixels"),
    "BUILTINS": ("tracer.builtin", "BUILTINS"),
}

__all__ = list(_LAZY)


def __getattr__(name: str):
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'tracer' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), attr)
    globals()[name] = value
    return value
