"""The nesting check of a camera JSON or TOML skips exactly the strings the parsers read, in every form, in memory
bounded by the text's bytes.

Outside values: Python's ``json`` (json.dumps writes each string, json.loads reads it back) and ``tomllib`` (each
TOML form of a string, basic, literal and both multi-line forms, kept only where tomllib reads back the same string):
the check must remove the string whole, so the brackets it holds are not counted as nesting. A multi-line basic
string holding an escaped quote just before three quotes (a backslash, then four quotes) was closed there, and a
valid file whose string held 70 ``[`` was refused as nested 70 deep."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib

from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.inputs.safeload import _JSON_STRING, _TOML_STRING, load_toml, text_depth

TEXT = st.text(st.sampled_from(list("ab[]{}\"'\\\n\t#u0 \u00e9\u2028\x00\x7f")) | st.characters(), max_size=30)
ESCAPES = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r", "\b": "\\b", "\f": "\\f"}


def _toml_forms(s: str) -> list[str]:
    basic = "".join(ESCAPES.get(c) or (f"\\u{ord(c):04X}" if ord(c) < 0x20 or ord(c) == 0x7F else c) for c in s)
    return ['"' + basic + '"', "'" + s + "'", '"""' + basic.replace("\\n", "\n") + '"""', '"""' + s + '"""',
            "'''" + s + "'''"]


@settings(max_examples=400, deadline=None)
@given(TEXT, st.booleans())
def test_json_strings_are_skipped_whole(s, ascii_only):
    r = json.dumps(s, ensure_ascii=ascii_only)
    doc = '{"k": ' + r + ", " + r + ": [[1]]}"
    assert json.loads(doc)[s] == [[1]]
    assert _JSON_STRING.sub("", doc) == "{: , : [[1]]}"
    assert text_depth(doc) == 3


@settings(max_examples=400, deadline=None)
@given(TEXT)
def test_toml_strings_are_skipped_whole_in_every_form(s):
    for form in _toml_forms(s):
        doc = "k = " + form + '\nv = [[1]] # a "comment\n'
        try:
            if tomllib.loads(doc)["k"] != s:
                continue
        except tomllib.TOMLDecodeError:
            continue  # a form this string cannot take
        assert _TOML_STRING.sub("", doc) == "k = \nv = [[1]] \n", doc
        assert text_depth(doc, _TOML_STRING) == 2


def test_an_escaped_quote_in_a_multi_line_string_does_not_close_it():
    doc = 'k = """\\"""' + "[" * 70 + '"""\nj = """a""""\n'  # (j's text ends with a quote)
    assert tomllib.loads(doc) == {"k": '"""' + "[" * 70, "j": 'a"'}
    assert load_toml(doc, "camera.toml") == tomllib.loads(doc)


CHILD = r"""
import resource
from lenslab.inputs.safeload import _TOML_STRING, text_depth
Q, A = chr(34), chr(39)
docs = ['{' + Q + 'k' + Q + ': ' + Q + (chr(92) * 2 + 'n') * 3_333_333 + Q + '}', 'k = ' + Q * 3 + ('a' + Q) * 5_000_000 + Q * 3,
        'k = ' + A * 3 + ('a' + A) * 5_000_000 + A * 3]
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
depths = [text_depth(docs[0]), text_depth(docs[1], _TOML_STRING), text_depth(docs[2], _TOML_STRING)]
print(*depths, (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) // 1024)
"""


def test_ten_megabytes_of_escapes_and_quotes_take_no_memory_per_character():
    # a child process, so its peak resident memory is the check's alone: before, 10 MB of escapes in a JSON string
    # took 390 MB and 10 MB of 'a"' in a TOML multi-line string 850 MB (120 bytes a backtracking frame); the budget,
    # 60 MB, is a few copies of the text
    out = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, check=True, timeout=300)
    *depths, grown = map(int, out.stdout.split())
    assert depths == [1, 0, 0]
    assert grown < 60, f"{grown} MB"
