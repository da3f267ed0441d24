"""``lenslab camera convert --model`` on a terminal: a fit that takes longer than a second is named in one line
(``CAMERA: fitting the kannala-brandt model ...``) while it runs; the fitted camera is the one the fit gives
without it (the TUM-VI double-sphere camera re-expressed as Kannala-Brandt, within docs/cameras.md's 0.05 px aim).
The test waits for the line (a state), never for a duration."""

from __future__ import annotations

import io
import time

from lenslab.cli.main import main
from lenslab.jobs import progress

CAMERA = ("double-sphere:fx=158.286,fy=158.274,cx=254.961,cy=256.889,xi=-0.17734,alpha=0.59291,"
          "width=512,height=512")


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_fit_on_a_terminal_says_what_it_is_doing(tmp_path, monkeypatch, capsys):
    import lenslab.fit.convert as convert

    stream = Terminal()
    monkeypatch.setattr("sys.stderr", stream)
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    fit = convert.convert_lens

    def waiting(*args, **kwargs):  # the fit starts once the line is out, however busy the machine
        deadline = time.monotonic() + 60.0
        while "fitting" not in stream.getvalue() and time.monotonic() < deadline:
            time.sleep(0.01)
        return fit(*args, **kwargs)

    monkeypatch.setattr(convert, "convert_lens", waiting)
    out = tmp_path / "kb.yaml"
    assert main(["camera", "convert", CAMERA, "-o", str(out), "--model", "kannala-brandt"]) == 0
    lines = [line for line in stream.getvalue().splitlines() if "fitting" in line]
    assert lines == [f"{CAMERA}: fitting the kannala-brandt model over the field both cameras share..."]
    assert "aim:      RMS below 0.05 px over the shared field: met" in capsys.readouterr().out
    assert out.exists()


def test_off_a_terminal_nothing_is_said(tmp_path, capsys):
    assert main(["camera", "convert", CAMERA, "-o", str(tmp_path / "kb.yaml"), "--model", "kannala-brandt"]) == 0
    assert "fitting" not in capsys.readouterr().err
