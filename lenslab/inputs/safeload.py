"""Parsers for structured text from strangers: YAML, JSON, TOML and XML with bounded depth and size.

- YAML: the safe loader (no Python tags: a ``!!python/...`` tag is refused), at most
  :data:`MAX_ALIASES` aliases, nesting at most :data:`MAX_DEPTH` deep, and at most :data:`MAX_NODES`
  nodes once every alias is expanded (a "billion laughs" alias chain is refused before it is built or
  printed). ``tags`` adds constructors for named local tags such as OpenCV's ``!!opencv-matrix``.
- JSON and TOML: nesting measured on the text before the parser (recursive in CPython) sees it.
- XML: ``defusedxml`` (no DTD, no entity, no external reference), then the same depth bound.

Every failure is one line naming the file (``error`` gives the exception type, InputError by default);
values quoted from the file are cut to a few dozen characters.
"""

from __future__ import annotations

import re

from lenslab.errors import InputError, clip

MAX_DEPTH = 64
MAX_ALIASES = 256
MAX_NODES = 100_000

#: a quoted string as an unrolled loop (runs of plain characters, each escape between), every repeat possessive: an
#: alternation repeated per character, or a repeat that may give characters back, costs Python's regex engine a
#: backtracking frame per character or escape, 120 bytes each (1.2 GB for a 10 MB string; 390 MB for 10 MB of escapes)
_JSON_STRING = re.compile(r'"[^"\\\n]*+(?:\\.[^"\\\n]*+)*+"')
#: TOML's strings the same way; in a multi-line one an escaped quote (basic) or a quote or two not followed by a third
#: are its text, and up to two quotes before the closing three are its last characters
_TOML_STRING = re.compile(r'"""[^"\\]*+(?:(?:\\[\s\S]|"(?!""))[^"\\]*+)*+"{3,5}|\'\'\'[^\']*+(?:\'(?!\'\')[^\']*+)*+\'{3,5}'
                          r'|"[^"\\\n]*+(?:\\.[^"\\\n]*+)*+"|\'[^\'\n]*+\'|#[^\n]*+')


def text_depth(text: str, strings=_JSON_STRING) -> int:
    """Deepest nesting of ``[``/``{`` in ``text`` outside strings (and TOML comments)."""
    import numpy as np

    bare = strings.sub("", text)
    codes = np.frombuffer(bare.encode("utf-8", "replace"), np.uint8)
    step = (np.isin(codes, (0x5B, 0x7B)).astype(np.int32) - np.isin(codes, (0x5D, 0x7D)).astype(np.int32))
    return int(np.cumsum(step).max(initial=0))


def _too_deep(path, what, depth, error):
    return error(f"{path}: the {what} nests {depth} levels deep, more than the {MAX_DEPTH} a real file needs")


def load_json(text: str, path, error=InputError):
    import json

    depth = text_depth(text)
    if depth > MAX_DEPTH:
        raise _too_deep(path, "JSON", depth, error)
    try:
        return json.loads(text, parse_constant=lambda name: float(name))
    except (json.JSONDecodeError, RecursionError) as exc:
        raise error(f"{path}: not valid JSON ({getattr(exc, 'msg', type(exc).__name__)} at line "
                    f"{getattr(exc, 'lineno', '?')})") from None


def load_toml(text: str, path, error=InputError):
    import tomllib

    depth = text_depth(text, _TOML_STRING)
    if depth > MAX_DEPTH:
        raise _too_deep(path, "TOML", depth, error)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML ({clip(str(exc), 80)})") from None
    except RecursionError:
        raise _too_deep(path, "TOML", depth, error) from None


def _yaml_loader(tags):
    import yaml

    class Loader(yaml.SafeLoader):
        def __init__(self, stream):
            super().__init__(stream)
            self.depth = 0
            self.aliases = 0

        def compose_node(self, parent, index):
            if self.check_event(yaml.AliasEvent):
                self.aliases += 1
                if self.aliases > MAX_ALIASES:
                    raise yaml.YAMLError(f"more than {MAX_ALIASES} aliases")
            self.depth += 1
            if self.depth > MAX_DEPTH:
                raise yaml.YAMLError(f"nested more than {MAX_DEPTH} levels deep")
            try:
                return super().compose_node(parent, index)
            finally:
                self.depth -= 1

    for tag, build in (tags or {}).items():
        Loader.add_constructor(tag, build)
    return Loader


def _expanded_nodes(root) -> int:
    """Nodes of a composed YAML graph with every alias expanded (memoised: linear in the graph)."""
    import yaml

    sizes: dict[int, int] = {}

    def size(node, depth=0):
        key = id(node)
        if key in sizes:
            return sizes[key]
        n = 1
        if isinstance(node, yaml.SequenceNode):
            n += sum(size(v, depth + 1) for v in node.value)
        elif isinstance(node, yaml.MappingNode):
            n += sum(size(k, depth + 1) + size(v, depth + 1) for k, v in node.value)
        sizes[key] = min(n, MAX_NODES + 1)
        return sizes[key]

    return size(root)


def load_yaml(text: str, path, error=InputError, tags: dict | None = None):
    """A YAML document as Python data (see the module docstring)."""
    import yaml

    loader = None
    try:
        loader = _yaml_loader(tags)(text)
        node = loader.get_single_node()
        if node is None:
            return None
        nodes = _expanded_nodes(node)
        if nodes > MAX_NODES:
            raise error(f"{path}: the YAML expands to more than {MAX_NODES} values through its aliases; "
                        "refused as an alias bomb")
        return loader.construct_document(node)
    except yaml.YAMLError as exc:
        said = str(exc).strip().splitlines()
        reason = said[0] if said else type(exc).__name__
        if "could not determine a constructor" in str(exc):
            m = re.search(r"tag '([^']*)'", str(exc))
            reason = f"the tag {clip(m.group(1) if m else '?')} is not allowed"
        raise error(f"{path}: not a valid or safe YAML file ({reason[:100]})") from None
    except RecursionError:
        raise _too_deep(path, "YAML", MAX_DEPTH, error) from None
    finally:
        if loader is not None:
            loader.dispose()


def load_xml(text: str, path, error=InputError):
    """The root element of an XML document; DTDs, entities and external references are refused."""
    import defusedxml
    import defusedxml.ElementTree as DET
    from xml.etree.ElementTree import ParseError

    try:
        root = DET.fromstring(text.encode("utf-8") if isinstance(text, str) else text, forbid_dtd=True)
    except defusedxml.DefusedXmlException as exc:
        raise error(f"{path}: the XML holds a DTD or entity declaration, which lenslab refuses "
                    f"({type(exc).__name__})") from None
    except ParseError as exc:
        raise error(f"{path}: not valid XML ({clip(str(exc), 80)})") from None
    stack = [(root, 1)]
    while stack:
        el, d = stack.pop()
        if d > MAX_DEPTH:
            raise _too_deep(path, "XML", d, error)
        stack.extend((c, d + 1) for c in el)
    return root
