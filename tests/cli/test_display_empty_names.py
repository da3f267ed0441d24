"""An empty ``--view``, ``--display`` or ``--colorspace`` name is a usage error (exit 2), said in one line that
lists the names the OpenColorIO config offers, before any input is read: an empty name would otherwise hold in
every name, or fall back to the display's default view without a word. The expected names come from
PyOpenColorIO's own listing of the built-in config, never from lenslab."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main

ocio = pytest.importorskip("PyOpenColorIO")


def config():
    return ocio.Config.CreateFromFile("ocio://default")


def srgb_display() -> str:
    found = [d for d in config().getDisplays() if d.split(" - ")[0] == "sRGB"]
    assert len(found) == 1
    return found[0]


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["tonemap"]])
@pytest.mark.parametrize("option, expected", [
    ("--view", lambda: list(config().getViews(srgb_display()))),
    ("--display", lambda: list(config().getDisplays())),
])
def test_empty_name_is_a_usage_error_listing_the_config_names(tmp_path, capsys, command, option, expected):
    missing = tmp_path / "not-read.exr"  # never read: the names are checked first
    out = tmp_path / "out.png"
    argv = [command[0], str(missing), *command[1:], "-o", str(out), "--display", "sRGB", option, ""]
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    names = expected()
    assert len(names) > 1
    assert err[0].endswith("; ".join(names)), err[0]
    assert "not-read" not in err[0]
    assert not out.exists()


def test_blank_view_is_refused_not_the_default(tmp_path, capsys):
    views = list(config().getViews(srgb_display()))
    argv = ["tonemap", str(tmp_path / "x.exr"), "-o", str(tmp_path / "o.png"), "--display", "sRGB", "--view", "  "]
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "; ".join(views) in err
    assert config().getDefaultView(srgb_display()) in views
