"""A registry's ``find`` hook: a lookup loads only what registers the name asked for; listing, an alias ``find``
does not bring, and an unknown name (whose error lists every valid name) still run the full loader, once."""

from __future__ import annotations

import pytest

from lenslab.registry import Registry


def _table():
    calls = {"find": [], "load": 0}
    modules = {"red": ("red", "scarlet"), "blue": ("blue", "navy")}

    def find(key):
        calls["find"].append(key)
        if key in modules and key not in table._entries:
            table.add(key, modules[key][0], aliases=modules[key][1:])

    def load():
        calls["load"] += 1
        for name, (value, *aliases) in modules.items():
            if name not in table._entries:
                table.add(name, value, aliases=aliases)
        table.sort(lambda entry: list(modules).index(entry.name))

    table = Registry("colour", KeyError, load=load, find=find)
    return table, calls


def test_a_lookup_runs_find_alone():
    table, calls = _table()
    assert table["blue"] == "blue" and "blue" in table and table.canonical("Blue") == "blue"
    assert calls == {"find": ["blue"], "load": 0}


def test_listing_after_a_lookup_loads_all_in_the_loaders_order():
    table, calls = _table()
    table.lookup("blue")
    assert table.names() == ["red", "blue"] and calls["load"] == 1


def test_an_alias_find_does_not_bring_and_an_unknown_name_load_everything():
    table, calls = _table()
    assert table["navy"] == "blue" and calls["load"] == 1
    with pytest.raises(KeyError, match="valid: red, blue"):
        table.lookup("green")
    assert calls["load"] == 1  # once


def test_a_private_name_imports_no_module():
    # "__init__" is an identifier and every model package has one: a lookup must not import the packages'
    # __init__ files again as modules of their own
    from lenslab.lenses.registry import model_modules

    assert model_modules("__init__") == [] and model_modules("_private") == []
