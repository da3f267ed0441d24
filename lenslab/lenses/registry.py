"""The registry of lens models (a :class:`lenslab.registry.Registry`), and the spec syntax every command uses.

Models are found like format plugins: every module in the model sub-packages of :mod:`lenslab.lenses`
(``projections``, ``panoramas``, ``multiview``, ``distortion``, ``calibrated``, ``lensfun``, or a new
one) is imported on first use, and each class it decorates with :func:`register` joins the registry
under its ``name`` and ``aliases``. A new model is one module dropped into one of those packages.

A spec is ``name`` or ``name:key=value,key=value``, for example ``fisheye:fov=180,mapping=equisolid``,
``swirl:amount=6`` or ``pincushion:k1=0.3,k2=0.05,fov=90``. Unknown names or parameters are errors that
list the valid ones.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from lenslab.errors import LensError

if TYPE_CHECKING:
    from lenslab.lenses.core.base import Lens

from lenslab.registry import Registry

#: sub-packages of lenslab.lenses that hold machinery, not models (never scanned for models)
MACHINERY = ("core", "formulas")


def load_models() -> None:
    """Import every model module so that their :func:`register` decorators run: each module of each
    sub-package of :mod:`lenslab.lenses` except :data:`MACHINERY` (and any model module left at the
    top level). Modules named ``kernels`` or ``*_kernels`` hold no models and are skipped."""
    import importlib
    import pkgutil

    import lenslab.lenses as package

    def scan(pkg) -> None:
        for info in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
            if info.name in MACHINERY or info.name == "registry" or info.name.endswith("kernels"):
                continue
            module = importlib.import_module(f"{pkg.__name__}.{info.name}")
            if info.ispkg:
                scan(module)

    scan(package)
    # one order whatever was looked up before (a lookup imports its model's module first): the modules' order
    order = {name: i for i, name in enumerate(sorted(m for m in sys.modules if m.startswith(package.__name__ + ".")))}
    REGISTRY.sort(lambda entry: order.get(entry.value.__module__, len(order)))


def model_modules(name: str) -> list[str]:
    """The modules that may register the model ``name``, found without importing any: the model modules
    named for it (``tan-fisheye``: ``projections/tan_fisheye.py``), else those whose text holds it quoted
    (``"mercator"`` in ``projections/cylindrical.py``). A hint only: what they do not register, a full
    :func:`load_models` finds."""
    import os

    import lenslab.lenses as package

    stem = name.replace("-", "_")
    if not stem.isidentifier() or stem.startswith("_") or stem == "registry" or stem.endswith("kernels"):
        return []
    models = [(sub, os.path.join(base, sub)) for base in package.__path__ for sub in sorted(os.listdir(base))
              if sub not in MACHINERY and os.path.isfile(os.path.join(base, sub, "__init__.py"))]
    named = [f"{package.__name__}.{sub}.{stem}" for sub, folder in models
             if os.path.isfile(os.path.join(folder, stem + ".py"))]
    if named:
        return named
    quoted = (f'"{name}"', f"'{name}'")
    found = []
    for sub, folder in models:
        for file in sorted(os.listdir(folder)):
            if file.endswith(".py") and file != "__init__.py" and not file[:-3].endswith("kernels"):
                with open(os.path.join(folder, file), encoding="utf-8") as f:
                    text = f.read()
                if any(q in text for q in quoted):
                    found.append(f"{package.__name__}.{sub}.{file[:-3]}")
    return found


def find_model(name: str) -> None:
    """Import the modules of :func:`model_modules`: a command that names its lenses loads those alone."""
    import importlib

    for module in model_modules(name):
        importlib.import_module(module)


REGISTRY: Registry[type] = Registry("lens model", LensError, load=load_models, find=find_model)


def register(cls):
    """Class decorator: add a :class:`~lenslab.lenses.core.base.Lens` subclass under ``cls.name``, with
    its ``aliases``, ``summary``, ``references`` and ``examples`` (class attributes)."""
    points = cls.__dict__.get("reference_points", ())
    references = getattr(cls, "references", ()) or tuple(dict.fromkeys(p.source for p in points))
    REGISTRY.add(cls.name, cls, aliases=cls.__dict__.get("aliases", ()), summary=getattr(cls, "summary", ""),
                 references=references, examples=cls.__dict__.get("examples", ()),
                 capabilities={"reference_points": points, "fit_examples": cls.__dict__.get("fit_examples", ())})
    return cls


def parse_spec(spec: str) -> tuple[str, dict[str, str]]:
    """Split ``name:key=value,...`` into the name and a dict of raw string values."""
    if not isinstance(spec, str) or not spec.strip():
        raise LensError(f"empty lens spec; valid models: {', '.join(sorted(REGISTRY))}")
    name, _, rest = spec.strip().partition(":")
    name = name.strip().lower()
    values: dict[str, str] = {}
    if rest.strip():
        # a model may take its first value without a key, e.g. ``tiled:2x2`` for ``tiled:grid=2x2``
        positional = getattr(REGISTRY.get(name), "positional", None)
        for i, item in enumerate(split_items(rest, spec)):
            if i == 0 and positional and "=" not in item and item.strip():
                item = f"{positional}={item}"
            key, eq, value = item.partition("=")
            key = key.strip()
            if not eq or not key:
                raise LensError(f"lens spec {spec!r}: expected key=value, got {item!r}")
            if key in values:
                raise LensError(f"lens spec {spec!r}: parameter {key} given twice")
            values[key] = value.strip()
    return name, values


def split_items(rest: str, spec: str) -> list[str]:
    """Split on commas outside double quotes; quotes around a value are dropped
    (``lens="Canon IXUS 400 & compatibles, with ..."`` keeps its comma)."""
    items, cur, quoted = [], [], False
    for ch in rest:
        if ch == '"':
            quoted = not quoted
        elif ch == "," and not quoted:
            items.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
    if quoted:
        raise LensError(f"lens spec {spec!r}: unbalanced double quote")
    return items + ["".join(cur)]


def lens_class(name: str, spec: str | None = None) -> type:
    """The class of a model by name or alias; LensError listing the valid models, the nearest first if one is close.
    ``spec``: the text the name came from; a bare word (no ``:``), which could have named a file, is said to be
    neither a model nor a file (a name only a file has, with a folder or an image's extension, is read as a file
    before it gets here, and a missing one is said missing)."""
    if name not in REGISTRY:
        from difflib import get_close_matches

        close = get_close_matches(name, list(REGISTRY), 1, 0.75) or _named_otherwise(name)  # (option hints' cut-off)
        meant = f" (did you mean {close[0]}?)" if close else ""
        word = spec.strip() if isinstance(spec, str) and ":" not in spec else None
        what = f"no lens model and no file named {word!r}" if word else f"unknown lens model {name!r}"
        raise LensError(f"{what}{meant}; valid models: {', '.join(sorted(REGISTRY))}")
    return REGISTRY[name]


def _named_otherwise(name: str) -> list[str]:
    """The spec a name that is no model may mean, where no model's name is close to it: a model's parameter that takes
    it as a value (``stereographic``: ``fisheye:mapping=stereographic``, the model of the shortest name first), else a
    model whose name begins it or that it begins (``equirectangular``: ``equirect``); [] if none."""
    key = name.strip().lower().replace("_", "-")
    if len(key) < 4:
        return []
    for model in sorted(REGISTRY, key=lambda m: (len(m), m)):
        for p in getattr(REGISTRY[model], "params", ()):
            if p.choices and key in p.choices:
                return [f"{model}:{p.name}={key}"]
    begun = sorted((m for m in REGISTRY if len(m) >= 4 and (key.startswith(m) or m.startswith(key))), key=len)
    return begun[-1:]


def make_lens(spec: str | dict[str, Any], size: tuple[int, int] | None = None, **overrides: Any) -> "Lens":
    """Build a lens from a spec and an image size.

    Parameters
    ----------
    spec : str or dict
        ``model:key=value,...`` (``lenslab lenses`` lists every model and parameter), a dict from
        ``Lens.to_dict()``, or a camera file (``cal.yaml``, ``cameras.txt#2``...) whose lens is read,
        scaled to ``size`` when that differs from its calibration size.
    size : tuple of int, optional
        ``(width, height)`` in pixels; a dict may carry its own ``size``, a camera file its own.
    **overrides
        Parameters that replace the spec's.

    Returns
    -------
    lenslab.lenses.Lens
        The lens: ``pixel_to_dir`` and ``dir_to_pixel`` map continuous pixel coordinates to unit
        ray directions and back.

    Raises
    ------
    lenslab.errors.LensError
        An unknown model or parameter (the message lists the valid ones), a value out of range, or no
        size.

    Examples
    --------
    >>> from lenslab import make_lens
    >>> lens = make_lens("fisheye:fov=180,mapping=equisolid", (512, 512))
    >>> lens.spec()
    'fisheye:fov=180,mapping=equisolid'
    >>> dirs, valid = lens.pixel_to_dir([[256.0, 256.0], [512.0, 256.0]])  # the centre; the rim
    >>> dirs.round(6).tolist(), valid.tolist()
    ([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], [True, True])
    """
    from lenslab.lens_sources import reader_for

    read = reader_for(spec)  # a calibration file (OpenCV, Kalibr, COLMAP, OCamCalib, TOML): FILE or FILE#ID
    if read is not None:
        return read(spec, size)
    if isinstance(spec, dict):
        values = dict(spec)
        name = str(values.pop("model", "")).lower()
        dict_size = values.pop("size", None)
        size = size or (tuple(dict_size) if dict_size is not None else None)
    else:
        name, values = parse_spec(spec)
    values.update(overrides)
    cls = lens_class(name, spec if isinstance(spec, str) else None)
    if size is None:
        size = getattr(cls, "default_size", None)
        if size is None:
            raise LensError(f"lens {name}: an image size (width, height) is needed")
    if hasattr(cls, "from_values"):
        return cls.from_values(size[0], size[1], values)
    # the image's size, which only a calibrated model's spec holds (as its parameters)
    sized = sorted({"width", "height"} & set(values) - {p.name for p in cls.params})
    if sized:
        known = ", ".join(p.name for p in cls.params) or "none"
        raise LensError(f"{cls.name}: unknown parameter(s) {', '.join(sized)}; valid: {known} (the image's size is "
                        "given apart: --size WxH)")
    return cls(size[0], size[1], **values)
