"""An option a command does not have is a usage error (exit 2, one line) blamed on that command and pointing
at its own ``--help``, as argparse reports every other mistake of a subcommand; not on the whole program."""

from __future__ import annotations

import pytest

from lenslab.cli.main import main as lenslab
from tracer.cli import main as tracer


@pytest.mark.parametrize("main, argv, prog", [
    (lenslab, ["tonemap", "in.exr", "-o", "out.png", "--gamma", "2.2"], "lenslab tonemap"),
    (lenslab, ["convert", "in.exr", "--to", "png", "--colour", "x"], "lenslab convert"),
    (lenslab, ["fit", "lens", "--from", "fisheye", "--model", "fisheye", "--bogus"], "lenslab fit lens"),
    (lenslab, ["camera", "show", "cam.yaml", "--bogus"], "lenslab camera show"),
    (tracer, ["render", "-o", "out.exr", "--bogus"], "tracer render"),
    (lenslab, ["--bogus"], "lenslab"),
])
def test_unknown_option_is_blamed_on_its_command(tmp_path, monkeypatch, capsys, main, argv, prog):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith(f"{prog}: error: unrecognized arguments: ")
    assert err[0].endswith(f"(see '{prog} --help')")
    assert list(tmp_path.iterdir()) == []
