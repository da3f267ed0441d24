"""The one registry type (lenslab.registry.Registry) that lenses, curves, formats, calibration files and
commands share: canonical names, aliases, errors that list the valid names, a loader run once."""

from __future__ import annotations

import pytest

from lenslab.errors import FormatError, LensError
from lenslab.registry import Registry


def test_names_aliases_and_lookups():
    table = Registry("widget", LensError)
    table.add("alpha", 1, aliases=("first", "A1"), summary="the first")
    table.add("beta", 2)
    assert list(table) == ["alpha", "beta"] and len(table) == 2  # canonical names only, in order
    assert table["FIRST"] == 1 and "a1" in table and table.canonical(" First ") == "alpha"
    assert table.get("gamma") is None and table.get("gamma", 7) == 7
    assert table.entry("first").summary == "the first" and table.aliases() == {"first": "alpha", "a1": "alpha"}
    with pytest.raises(LensError, match=r"unknown widget 'gamma'; valid: alpha, beta"):
        table.lookup("gamma")


@pytest.mark.parametrize("name,aliases", [("alpha", ()), ("gamma", ("first",)), ("first", ()), ("", ())])
def test_a_name_is_taken_once(name, aliases):
    table = Registry("widget")
    table.add("alpha", 1, aliases=("first",))
    with pytest.raises(RuntimeError):
        table.add(name, 2, aliases=aliases)


def test_the_loader_runs_once_on_first_use():
    calls = []
    table = Registry("widget", load=lambda: (calls.append(1), table.add("late", 3)))
    assert calls == []
    assert "late" in table and table["late"] == 3 and list(table) == ["late"]
    assert calls == [1]


def test_discard_removes_a_member_and_its_aliases():
    table = Registry("widget")
    table.add("alpha", 1, aliases=("first",))
    table.discard("first")
    assert "alpha" not in table and "first" not in table


def test_every_kind_of_thing_has_one():
    from lenslab.calibfiles import FORMATS as CALIBRATION
    from lenslab.cli.main import COMMANDS
    from lenslab.io.registry import formats
    from lenslab.lenses import REGISTRY
    from lenslab.tone import CURVES

    for table in (REGISTRY, CURVES, formats(), CALIBRATION, COMMANDS):
        assert isinstance(table, Registry) and len(table) > 0
    assert formats().canonical("JPEG") == "jpg" and formats().canonical("tif") == "tiff"
    with pytest.raises(FormatError, match="valid: exr, hdr"):
        formats().lookup("webp")
    assert CALIBRATION.canonical("ocamcalib") == "ocam" and COMMANDS["warp"][0] == "warp"


def test_threads_wait_for_the_loader():
    import threading

    started, release = threading.Event(), threading.Event()

    def load():
        started.set()
        release.wait(timeout=60)
        table.add("slow", 1)

    table = Registry("widget", load=load)
    loader = threading.Thread(target=lambda: "slow" in table)
    loader.start()
    assert started.wait(timeout=60)
    seen = []
    other = threading.Thread(target=lambda: seen.append("slow" in table))
    other.start()
    release.set()  # the other thread asked while the loader ran: it must see the whole registry
    loader.join(60)
    other.join(60)
    assert seen == [True]
