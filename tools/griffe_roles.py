"""A griffe extension for the API reference: the docstrings' reStructuredText roles as code.

lenslab's docstrings name other objects the way ``help()`` and Sphinx read them (``:func:`warp```,
``:class:`~lenslab.lenses.Camera```); the site shows each as inline code (``lenslab.lenses.Camera``,
or ``Camera`` with the ``~``), and ``double backticks`` as single ones, so the page never shows the
role's markup. Named in mkdocs.yml under the python handler's ``extensions``.
"""

from __future__ import annotations

import re
from typing import Any

import griffe

ROLE = re.compile(r":(?:func|meth|class|mod|data|attr|exc|obj):`~?([^`]+)`")


def _code(m: re.Match) -> str:
    target = m.group(1)
    shown = target.rsplit(".", 1)[-1] if m.group(0).split("`")[1].startswith("~") else target
    return f"`{shown}`"


def plain(text: str) -> str:
    """``text`` with roles as inline code."""
    return ROLE.sub(_code, text)


class RolesAsCode(griffe.Extension):
    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = plain(obj.docstring.value)
