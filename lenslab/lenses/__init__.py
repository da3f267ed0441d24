"""Lens models: pixel <-> ray direction, both ways, one small class per model.

``make_lens("fisheye:fov=180,mapping=equisolid", (1024, 1024))`` builds one from a spec;
``REGISTRY`` maps every model name to its class; :class:`Camera` adds a pose and an eye point.
"""

from __future__ import annotations

# Modules whose classes register themselves; add a model by adding its module here.
MODEL_MODULES = ("equirect", "perspective", "fisheye", "seedfisheye", "cubemap", "swirl", "distortion", "brown", "tiled",
                 "eac", "dualfisheye", "cylindrical", "pannini", "worldmaps", "octahedron", "presets",
                 "opencv", "kannala_brandt", "omnidir", "double_sphere", "eucm", "ocam", "devernay_fov",
                 "chroma", "lensfun_profile", "division", "fisheye624", "stereo", "ball", "tetrahedron", "barrel",
                 "tsp", "globe")

from lenslab.lenses.base import Lens, Param  # noqa: E402
from lenslab.lenses.camera import Camera, rotation_between, sample_offsets  # noqa: E402
from lenslab.lenses.pose import Pose, look_at_matrix, ypr_matrix  # noqa: E402
from lenslab.lenses.registry import REGISTRY, make_lens, parse_spec, register, _load_models  # noqa: E402

_load_models()

from lenslab.lenses.cameraio import load_camera, load_cameras, save_camera, save_cameras  # noqa: E402

__all__ = [
    "Lens", "Param", "Camera", "Pose", "REGISTRY", "make_lens", "parse_spec", "register",
    "rotation_between", "sample_offsets", "look_at_matrix", "ypr_matrix",
    "load_camera", "load_cameras", "save_camera", "save_cameras",
]
