"""The curve registry: every tone curve by name, with its declared parameters.

A curve module registers itself with :func:`register`; :data:`CURVES` (a :class:`lenslab.registry.Registry`)
finds every such module of :mod:`lenslab.tone` on first use, so a new curve is one module. The command
line (``--tone``, ``lenslab curves --list``), the chart, the fits, the docs and the tests all read it. An unknown name or a bad
parameter raises :class:`lenslab.errors.ToneError` listing what is valid.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from lenslab.errors import ToneError
from lenslab.params import Param
from lenslab.registry import Registry

KINDS = ("scalar", "rgb", "image", "local")


@dataclass(frozen=True)
class Curve:
    """A registered tone curve.

    ``kind`` says how it acts: ``"scalar"`` (one pure function of each value), ``"rgb"`` (acts on RGB
    triples: colour matrices or a cross-channel rule; on luminance or grey data it acts on (L, L, L)),
    ``"image"`` (a scalar curve whose scale comes from the image's log-average) or ``"local"``
    (OpenCV operators whose result at a pixel depends on the whole image; they always work on
    luminance with their own saturation control, so ``mode`` does not apply).

    ``build(params, scale)`` makes the kernel (see :mod:`lenslab.tone.kernels`) with the exposure
    ``scale`` folded in; ``build_grey`` the same curve on grey values for ``"rgb"`` curves; for
    ``"local"`` curves ``build(image, params, weights)`` maps a whole repaired, exposed image.
    ``check(params)`` completes the resolved parameters (values derived from others) and refuses
    combinations no single range can express.
    """

    name: str
    function: Callable
    params: tuple[Param, ...]
    kind: str
    summary: str
    build: Callable | None = field(default=None, repr=False)
    build_grey: Callable | None = field(default=None, repr=False)
    check: Callable[[dict], dict] | None = field(default=None, repr=False)
    #: why the curve gives the same image for any exposure (a note for a user who gives one), or "" when the
    #: exposure matters
    ignores_exposure: str = ""

    @property
    def doc(self) -> str:
        return (self.function.__doc__ or self.summary).strip()

    def resolve(self, params: dict | None = None) -> dict:
        """Validated parameters with defaults filled in; raises ToneError on unknown names or bad values."""
        params = dict(params or {})
        known = {p.name: p for p in self.params}
        unknown = [k for k in params if k not in known]
        if unknown:
            if known:
                valid = "; ".join(p.describe() for p in self.params)
                raise ToneError(f"curve {self.name!r} has no parameter {', '.join(map(repr, unknown))}; "
                                f"its parameters are: {valid}")
            raise ToneError(f"curve {self.name!r} takes no parameters (got {', '.join(map(repr, unknown))})")
        out = {}
        for p in self.params:
            given = params.get(p.name)
            out[p.name] = p.default if given is None else p.convert(f"curve {self.name!r}", given, ToneError)
        return self.check(out) if self.check else out


def curve_key(name: str) -> str:
    """Curve names are case-insensitive, and ``_`` and ``-`` are interchangeable."""
    return str(name).strip().lower().replace("_", "-")


def load_curves() -> None:
    """Import :mod:`lenslab.tone` (its curve modules, in the order users see them listed), then any other
    module of the package that registers a curve."""
    import importlib
    import pkgutil
    from pathlib import Path

    import lenslab.tone as package

    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda m: m.name):
        source = Path(package.__path__[0], info.name + ".py")
        if source.is_file() and "from lenslab.tone.registry import register" in source.read_text(encoding="utf-8"):
            importlib.import_module(f"lenslab.tone.{info.name}")


#: every tone curve, by name
CURVES: Registry[Curve] = Registry("tone curve", ToneError, load=load_curves, key=curve_key)


def register(name: str, kind: str, params: tuple[Param, ...] = (), build: Callable | None = None,
             build_grey: Callable | None = None, check: Callable[[dict], dict] | None = None,
             references: tuple[str, ...] = (), examples: tuple[str, ...] = (), ignores_exposure: str = ""):
    """Decorator: register the curve function it wraps as ``name`` (its docstring's first paragraph
    is the summary ``lenslab curves --list`` prints). ``ignores_exposure``: why the curve's result is the
    same for any exposure, said in a note when one is given."""
    if kind not in KINDS:  # pragma: no cover - a programming error in a curve module
        raise ValueError(f"curve kind {kind!r}; use one of {', '.join(KINDS)}")

    def deco(fn):
        first_paragraph = (fn.__doc__ or "").strip().split("\n\n")[0]
        summary = " ".join(line.strip() for line in first_paragraph.splitlines())
        CURVES.add(name, Curve(name, fn, tuple(params), kind, summary, build, build_grey, check, ignores_exposure),
                   summary=summary, capabilities={"kind": kind}, references=tuple(references),
                   examples=tuple(examples))
        return fn
    return deco


def curve_names() -> list[str]:
    """Every registered curve name, in the order they are listed to users.

    Returns
    -------
    list of str
        The names :func:`lenslab.tone.tonemap` takes as ``curve``.

    Examples
    --------
    >>> from lenslab.tone import curve_names
    >>> curve_names()[:4]
    ['clamp', 'gamma', 'reinhard', 'reinhard-extended']
    """
    return list(CURVES)


def get_curve(name: str) -> Curve:
    """The curve called ``name`` (case-insensitive; ``_`` and ``-`` are interchangeable).

    Parameters
    ----------
    name : str
        A curve name of :func:`curve_names`.

    Returns
    -------
    Curve
        Its record: ``name``, ``summary``, declared ``params`` (with ranges and defaults) and
        ``resolve(values)``, which checks values against them.

    Raises
    ------
    lenslab.errors.ToneError
        An unknown name; the message lists the valid ones.

    Examples
    --------
    >>> from lenslab.tone import get_curve
    >>> curve = get_curve("Reinhard_Extended")
    >>> curve.name, [p.name for p in curve.params], curve.resolve({"white": 2.0})
    ('reinhard-extended', ['white'], {'white': 2.0})
    """
    if name not in CURVES:
        raise ToneError(f"unknown tone curve {name!r}; valid curves: {', '.join(CURVES)}")
    return CURVES[name]


def describe_curves() -> str:
    """A plain-text listing of every curve: summary and parameters with ranges and defaults."""
    lines = []
    for c in CURVES.values():
        lines.append(f"{c.name:<18s} {c.summary}")
        for p in c.params:
            lines.append(f"{'':<20s}{p.describe()}")
    return "\n".join(lines)
