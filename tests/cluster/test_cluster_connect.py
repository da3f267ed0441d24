"""Where the scheduler is, said wrong: one line, the right exit code, no folder made, no traceback.

A scheduler that accepts the connection and never answers is a loopback socket server in this test:
the command gives up after ``--scheduler-timeout`` and says so in one line.
"""

from __future__ import annotations

import json
import socket
import threading
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from lenslab.cli.main import main as lenslab  # noqa: E402
from lenslab.io import write  # noqa: E402


@pytest.fixture()
def inputs(tmp_path) -> Path:
    folder = tmp_path / "in"
    folder.mkdir()
    for i in range(2):
        write(folder / f"frame{i}.exr", np.full((8, 16, 3), 0.5, np.float32))
    return folder


@pytest.fixture()
def silent_scheduler():
    """``tcp://127.0.0.1:PORT`` of a server that accepts every connection and never sends a byte."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(16)
    held, stop = [], threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    stop.set()
    thread.join()
    for conn in held:
        conn.close()
    server.close()


COMMANDS = [["convert", "--to", "pfm"], ["warp", "--to", "fisheye:fov=180"], ["tonemap"]]


@pytest.mark.slow
@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
def test_a_scheduler_that_never_answers_is_one_line(inputs, tmp_path, command, capsys, silent_scheduler):
    out = tmp_path / "out"
    status = lenslab([command[0], str(inputs), "-o", str(out), *command[1:], "--scheduler", silent_scheduler,
                      "--scheduler-timeout", "2"])
    err = capsys.readouterr().err
    assert status == 1, err  # the address may be right and the scheduler stuck: a failed start, not usage
    assert err.count("\n") == 1 and silent_scheduler in err and "Traceback" not in err, err
    assert not out.exists()


def _scheduler_files(tmp_path: Path) -> dict[str, str]:
    (tmp_path / "empty.json").write_text("")
    (tmp_path / "no-address.json").write_text(json.dumps({"type": "Scheduler", "id": "x"}))
    (tmp_path / "bad-address.json").write_text(json.dumps({"address": "not an address"}))
    (tmp_path / "deep.json").write_text("[" * 100000 + "]" * 100000)
    (tmp_path / "folder").mkdir()
    return {"/etc/passwd": "/etc/passwd", "empty": str(tmp_path / "empty.json"),
            "no address": str(tmp_path / "no-address.json"), "bad address": str(tmp_path / "bad-address.json"),
            "deep": str(tmp_path / "deep.json"), "a folder": str(tmp_path / "folder"),
            "missing": str(tmp_path / "missing.json"), "a device": "/dev/zero"}


BAD_ADDRESSES = ["not-an-address", "tcp://", "tcp://host", "tcp://host:0", "tcp://host:99999", "http://host:8786",
                 "host:port", "", "tcp://a b:1"]


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
@pytest.mark.parametrize("address", BAD_ADDRESSES)
def test_a_value_that_is_no_address_is_a_usage_error(inputs, tmp_path, command, address, capsys):
    out = tmp_path / "out"
    status = lenslab([command[0], str(inputs), "-o", str(out), *command[1:], "--scheduler", address])
    err = capsys.readouterr().err
    if address == "":  # an empty value means "no scheduler": the batch runs here
        assert status == 0, err
        return
    assert status == 2, err
    assert err.count("\n") == 1 and "--scheduler" in err and "Traceback" not in err, err
    assert not out.exists()


@pytest.mark.parametrize("case", ["/etc/passwd", "empty", "no address", "bad address", "deep", "a folder", "missing",
                                  "a device"])
def test_a_file_that_is_no_scheduler_file_is_a_usage_error(inputs, tmp_path, case, capsys):
    path = _scheduler_files(tmp_path)[case]
    out = tmp_path / "out"
    status = lenslab(["convert", str(inputs), "-o", str(out), "--to", "pfm", "--scheduler-file", path])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.count("\n") == 1 and "--scheduler-file" in err and "Traceback" not in err, err
    assert not out.exists()


def test_the_scheduler_timeout_defaults_to_15_seconds_and_must_be_positive(capsys):
    from lenslab.cli.main import build_parser

    assert build_parser().parse_args(["convert", "x.exr", "--to", "pfm"]).scheduler_timeout == 15.0
    for bad in ("0", "-1", "nan", "inf"):
        with pytest.raises(SystemExit) as stop:
            build_parser().parse_args(["convert", "x.exr", "--to", "pfm", "--scheduler-timeout", bad])
        assert stop.value.code == 2
    capsys.readouterr()
