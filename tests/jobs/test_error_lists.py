"""An error that lists the valid names (colour-science's ``validate_method`` style) shows every name on its one
line; only a list past 2000 characters is cut, between two names, with how many are left out."""

from __future__ import annotations

from lenslab.cli.main import main
from lenslab.errors import LensError
from lenslab.jobs.funnel import LIST_LIMIT, one_line


def test_an_unknown_lens_model_lists_every_model(tmp_path, capsys):
    from lenslab.lenses import REGISTRY

    assert main(["warp", str(tmp_path / "missing.exr"), "-o", str(tmp_path / "x.exr"), "--to", "nosuch"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no lens model and no file named 'nosuch'" in err
    listed = err.strip().split("valid models: ", 1)[1].split(", ")
    assert listed == sorted(REGISTRY)  # every name, whole: the registry's own list
    assert len(err) > 400  # longer than other messages may be


def test_a_very_long_list_is_cut_between_names_with_a_count():
    names = [f"name{i:04d}" for i in range(500)]
    text = one_line(LensError(f"unknown thing 'x'; valid things: {', '.join(names)}"))
    assert len(text) <= LIST_LIMIT
    head, more = text.rsplit(" and ", 1)
    shown = head.split("valid things: ", 1)[1].split(", ")
    assert shown == names[:len(shown)]  # whole names, in order
    assert more == f"{500 - len(shown)} more"


def test_other_long_messages_are_still_cut_at_400():
    text = one_line(LensError("y" * 5000))
    assert len(text) == 400 and text.endswith("...")
