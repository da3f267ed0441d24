"""Where the lens modules of the flat layout live now, so that their old import paths keep working.

``import lenslab.lenses.fisheye`` is ``lenslab.lenses.projections.fisheye``: a finder placed after
the ordinary ones resolves each old name below to the module that now holds it (the same module
object, not a copy). ``lenslab.lenses.calibrated`` is now a package that re-exports what the old
module held; ``lenslab.lenses.distortion`` is the package of distortion models (the division model
is :mod:`lenslab.lenses.distortion.division`).
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

#: old module name (below ``lenslab.lenses``) -> its place now
MOVED = {
    "base": "core.base",
    "protocol": "core.protocol",
    "camera": "core.camera",
    "pose": "core.pose",
    "cameraio": "core.cameraio",
    "wrapped": "core.wrapped",
    "solve": "formulas.solve",
    "radial": "formulas.radial",
    "perspective": "projections.perspective",
    "fisheye": "projections.fisheye",
    "equirect": "projections.equirect",
    "cylindrical": "projections.cylindrical",
    "pannini": "projections.pannini",
    "worldmaps": "projections.worldmaps",
    "seedfisheye": "projections.tan_fisheye",
    "cubemap": "panoramas.cubemap",
    "eac": "panoramas.eac",
    "dualfisheye": "panoramas.dualfisheye",
    "octahedron": "panoramas.octahedron",
    "presets": "panoramas.presets",
    "tiled": "multiview.tiled",
    "brown": "distortion.brown",
    "swirl": "distortion.swirl",
    "chroma": "distortion.chroma",
    "polydistort": "calibrated.polydistort",
    "opencv": "calibrated.opencv",
    "kannala_brandt": "calibrated.kannala_brandt",
    "omnidir": "calibrated.omnidir",
    "double_sphere": "calibrated.double_sphere",
    "eucm": "calibrated.eucm",
    "ocam": "calibrated.ocam",
    "devernay_fov": "calibrated.devernay_fov",
    "lensfun_profile": "lensfun.profile",
    "lensfun_db": "lensfun.database",
}


class MovedModuleFinder:
    """Resolves ``lenslab.lenses.<old name>`` to the module that now holds it: a meta path finder and its loader, by
    the methods the import system calls (``importlib.abc``'s classes, which a start-up would load, are not needed)."""

    PREFIX = "lenslab.lenses."

    def find_spec(self, fullname, path=None, target=None):
        if not fullname.startswith(self.PREFIX) or fullname[len(self.PREFIX):] not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def __init__(self):
        self._specs = {}

    def create_module(self, spec):
        module = importlib.import_module(self.PREFIX + MOVED[spec.name[len(self.PREFIX):]])
        self._specs[spec.name] = module.__spec__  # the import system overwrites it with the old name's
        return module

    def exec_module(self, module):
        """Nothing to run (the module was imported under its new name): give it back its own spec."""
        module.__spec__ = self._specs.pop(module.__spec__.name, module.__spec__)


def install() -> None:
    """Add the finder once, after the ordinary finders (real modules always win)."""
    if not any(isinstance(f, MovedModuleFinder) for f in sys.meta_path):
        sys.meta_path.append(MovedModuleFinder())
