"""Models that bend the normalised image plane and pass the result through a base model.

Swirl and the radial distortions are not projections of their own: they move the point ``(u, v)``
and hand it to a base model (perspective by default) that turns it into a direction. The spec names
the base and passes its parameters through, e.g. ``swirl:amount=6,base=fisheye,fov=180,mapping=equisolid``
or ``pincushion:k1=0.3,k2=0.05,fov=90``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import Lens, Param
from lenslab.lenses.registry import lens_class


def has_uv_maps(cls: type) -> bool:
    """True for models that work on normalised coordinates (and so can be bent by a wrapper)."""
    return cls.uv_to_dir is not Lens.uv_to_dir and cls.dir_to_uv is not Lens.dir_to_uv


BASE_PARAM = Param("base", "perspective", "model the bent image plane goes through (its parameters pass through)")


class Wrapped(Lens):
    """A bend of the normalised plane, ``(u, v) -> (u', v')``, followed by a base model.

    Subclasses set ``own_params`` (``params`` adds ``base``) and implement :meth:`bend`
    (pixel side -> base side) and :meth:`unbend` (its inverse), each with a validity mask.
    The base lens has the same image size; its own image bounds do not apply to the bent points
    (a swirled corner may leave the base's rectangle and still see a direction).
    """

    own_params: tuple[Param, ...] = ()

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        cls.params = tuple(cls.own_params) + (BASE_PARAM,)

    def __init__(self, width: int, height: int, **values: Any):
        own_names = {p.name for p in self.params}
        own = {k: v for k, v in values.items() if k in own_names}
        rest = {k: v for k, v in values.items() if k not in own_names}
        base_name = str(own.get("base", BASE_PARAM.default)).strip().lower()
        own["base"] = base_name
        base_cls = lens_class(base_name)
        if not has_uv_maps(base_cls):
            raise LensError(
                f"{self.name}: base={base_name} cannot be bent (it is not a single projection of the "
                f"normalised image plane); use perspective, fisheye, tan-fisheye, equirect or another bent model"
            )
        known = {p.name for p in base_cls.params}
        unknown = sorted(set(rest) - known)
        if unknown:
            raise LensError(
                f"{self.name}: unknown parameter(s) {', '.join(unknown)}; valid: "
                + ", ".join([p.name for p in self.params] + [f"{n} (of base {base_name})" for n in known])
            )
        super().__init__(width, height, **own)
        self.base_lens = base_cls(width, height, **rest)

    def param_values(self) -> dict[str, Any]:
        out = {p.name: getattr(self, p.name) for p in self.params}
        for k, v in self.base_lens.param_values().items():
            out.setdefault(k, v)
        return out

    def spec(self) -> str:
        own = Lens.spec(self)
        base = self.base_lens.spec()
        _, _, base_params = base.partition(":")
        return own + ("," + base_params if base_params else "")

    # -- the bend ----------------------------------------------------------------------------
    def bend(self, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def unbend(self, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def uv_to_dir(self, uv):
        bent, ok = self.bend(uv)
        d, valid = self.base_lens.uv_to_dir(bent)
        return d, valid & ok

    def dir_to_uv(self, d):
        bent, valid = self.base_lens.dir_to_uv(d)
        uv, ok = self.unbend(bent)
        return uv, valid & ok
