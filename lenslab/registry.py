"""The one registry type: lenses, tone curves, file formats, calibration files, warp filters and commands.

A :class:`Registry` maps canonical names to members, with aliases (old or alternative names that
resolve to a canonical one), and keeps for each member an :class:`Entry` with what the docs, the
command line and the conformance tests read: a one-line summary, declared capabilities, outside
references (papers, libraries) and example specs. Members are found by a loader the registry runs
once, on first use (the plugin modules of a package), so nothing keeps a hand-written list.

An unknown name raises the registry's error type with every valid name, as colour-science's
``validate_method`` does:

>>> from lenslab.registry import Registry
>>> colours = Registry("colour", KeyError)
>>> _ = colours.add("red", 0xFF0000, aliases=("scarlet",))
>>> colours["Scarlet"] == colours["red"]
True
>>> colours.canonical("scarlet")
'red'
>>> colours.lookup("blue")
Traceback (most recent call last):
...
KeyError: "unknown colour 'blue'; valid: red"
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Callable, Generic, Iterator, TypeVar

T = TypeVar("T")


@dataclass(frozen=True)
class Entry(Generic[T]):
    """One registered member and what is said about it.

    ``capabilities``: what the member declares it does (the conformance suite checks each claim);
    ``references``: where its numbers come from (a paper, OpenCV, lensfun, ...); ``examples``: specs
    or calls that show it, used by the docs and run by the tests.
    """

    name: str
    value: T
    aliases: tuple[str, ...] = ()
    summary: str = ""
    capabilities: dict[str, Any] = field(default_factory=dict)
    references: tuple[str, ...] = ()
    examples: tuple[str, ...] = ()


def plain_key(name: str) -> str:
    """Names compare case-insensitively, with surrounding spaces removed."""
    return str(name).strip().lower()


class Registry(Mapping, Generic[T]):
    """Canonical name -> member, plus aliases; a read-only mapping over the canonical names.

    ``kind`` names the members in messages (``"lens model"``); ``error`` is the exception an unknown
    name raises; ``load`` (optional) is called once before the first lookup to import the modules
    that :meth:`add` their members; ``key`` normalises names (default: case-insensitive). ``find``
    (optional, with ``load``) is given a name not registered yet before ``load`` runs, and may import
    only the module that registers it: a lookup of one member then costs one module, while listing the
    members (and any name ``find`` does not bring) still runs ``load``.
    """

    def __init__(self, kind: str, error: type[Exception] = KeyError, load: Callable[[], None] | None = None,
                 key: Callable[[str], str] = plain_key, find: Callable[[str], None] | None = None):
        self.kind = kind
        self.error = error
        self._load = load
        self._find = find
        self._loaded = load is None
        self._loading = False
        self._lock = threading.RLock()
        self._key = key
        self._entries: dict[str, Entry[T]] = {}
        self._aliases: dict[str, str] = {}

    @classmethod
    def from_mapping(cls, kind: str, mapping: Mapping, error: type[Exception] = KeyError,
                     summary: Callable[[Any], str] | None = None) -> "Registry":
        """A registry of the items of ``mapping`` (in its order), each summary from ``summary(value)``."""
        table = cls(kind, error)
        for name, value in mapping.items():
            table.add(name, value, summary=summary(value) if summary else "")
        return table

    # -- filling ------------------------------------------------------------------------------
    def add(self, name: str, value: T, *, aliases=(), summary: str = "", capabilities: dict | None = None,
            references=(), examples=()) -> T:
        """Register ``value`` as ``name`` (and its aliases); a name taken twice is a programming error."""
        key = self._key(name)
        taken = [n for n in (key, *map(self._key, aliases)) if n in self._entries or n in self._aliases]
        if not key or taken:
            raise RuntimeError(f"{self.kind} name {name!r} missing or registered twice ({', '.join(taken)})")
        self._entries[key] = Entry(key, value, tuple(map(self._key, aliases)), summary, dict(capabilities or {}),
                                   tuple(references), tuple(examples))
        for alias in aliases:
            self._aliases[self._key(alias)] = key
        return value

    def discard(self, name: str) -> None:
        """Remove a member and its aliases (a plugin unloaded at run time); unknown names are ignored."""
        key = self._aliases.get(self._key(name), self._key(name))
        entry = self._entries.pop(key, None)
        for alias in entry.aliases if entry else ():
            self._aliases.pop(alias, None)

    def ensure_loaded(self) -> None:
        """Run the loader once. Other threads wait until it has finished; the loading thread itself (a
        module that looks a name up while it registers) sees what is registered so far."""
        if self._loaded:
            return
        with self._lock:  # re-entrant: the loading thread may come back here
            if self._loaded or self._loading:
                return
            self._loading = True
            try:
                self._load()
                self._loaded = True
            finally:
                self._loading = False

    def sort(self, key: Callable[[Entry[T]], Any]) -> None:
        """Put the members in the order of ``key`` (stable): a loader's order, whatever was looked up first."""
        with self._lock:
            self._entries = dict(sorted(self._entries.items(), key=lambda item: key(item[1])))

    def _resolve(self, name: str) -> str:
        """The canonical key of ``name`` if it is registered, loading only what is needed: what ``find``
        imports for it, else everything; the key itself (not registered) otherwise."""
        key = self._key(name)
        if key not in self._entries and key not in self._aliases and not self._loaded:
            if self._find is not None and not self._loading:
                with self._lock:
                    self._find(key)
            if key not in self._entries and key not in self._aliases:
                self.ensure_loaded()
        return self._aliases.get(key, key)

    # -- lookup -------------------------------------------------------------------------------
    def canonical(self, name: str) -> str:
        """The canonical name of ``name`` or an alias of it; the registry's error listing valid names."""
        key = self._resolve(name)
        if key not in self._entries:
            raise self.error(f"unknown {self.kind} {name!r}; valid: {', '.join(self.names())}")
        return key

    def entry(self, name: str) -> Entry[T]:
        return self._entries[self.canonical(name)]

    def lookup(self, name: str) -> T:
        """The member called ``name`` (or an alias of it); the registry's error listing valid names."""
        return self.entry(name).value

    def get(self, name: str, default: Any = None) -> Any:  # type: ignore[override]
        """The member called ``name`` (or an alias), or ``default``."""
        return self[name] if name in self else default

    def names(self) -> list[str]:
        """Canonical names, in registration order."""
        self.ensure_loaded()
        return list(self._entries)

    def aliases(self) -> dict[str, str]:
        """Alias -> canonical name."""
        self.ensure_loaded()
        return dict(self._aliases)

    def entries(self) -> list[Entry[T]]:
        self.ensure_loaded()
        return list(self._entries.values())

    # -- Mapping (canonical names; aliases are accepted by [] and in) ---------------------------
    def __getitem__(self, name: str) -> T:
        return self._entries[self._resolve(name)].value

    def __contains__(self, name: object) -> bool:
        if not isinstance(name, str):
            return False
        return self._resolve(name) in self._entries

    def __iter__(self) -> Iterator[str]:
        self.ensure_loaded()
        return iter(list(self._entries))

    def __len__(self) -> int:
        self.ensure_loaded()
        return len(self._entries)

    def __repr__(self) -> str:
        return f"<Registry of {len(self._entries)} {self.kind}s>"
