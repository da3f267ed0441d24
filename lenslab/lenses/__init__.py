"""Lens models: pixel <-> ray direction, both ways, one small class per model.

``make_lens("fisheye:fov=180,mapping=equisolid", (1024, 1024))`` builds one from a spec;
``REGISTRY`` maps every model name (and alias) to its class; :class:`Camera` adds a pose and an eye point.

The package is in two levels: :mod:`lenslab.lenses.formulas` holds the pure formulas on bare arrays,
and the model sub-packages hold thin classes that bind them to parameters and an image size:
:mod:`~lenslab.lenses.projections`, :mod:`~lenslab.lenses.panoramas` (360 formats),
:mod:`~lenslab.lenses.multiview`, :mod:`~lenslab.lenses.distortion`, :mod:`~lenslab.lenses.calibrated`
and :mod:`~lenslab.lenses.lensfun`. :mod:`lenslab.lenses.core` is what they all build on. Models are
discovered: a new one is a module in one of the model sub-packages, and nothing else names it.
"""

from __future__ import annotations

from lenslab.lenses.core import moved

moved.install()  # the module paths of the flat layout (lenslab.lenses.fisheye, ...) keep working

from lenslab.lenses.core.base import Lens, Param  # noqa: E402
from lenslab.lenses.core.camera import Camera, rotation_between, sample_offsets  # noqa: E402
from lenslab.lenses.core.pose import Pose, look_at_matrix, ypr_matrix  # noqa: E402
from lenslab.lenses.registry import REGISTRY, make_lens, parse_spec, register  # noqa: E402
from lenslab.lenses.core.cameraio import load_camera, load_cameras, save_camera, save_cameras  # noqa: E402

__all__ = [
    "Lens", "Param", "Camera", "Pose", "REGISTRY", "make_lens", "parse_spec", "register",
    "rotation_between", "sample_offsets", "look_at_matrix", "ypr_matrix",
    "load_camera", "load_cameras", "save_camera", "save_cameras",
]
