"""A Dask worker of several threads runs several files at once (``dask worker`` gives a worker one thread per core
unless told otherwise): each file's notes are still its own, as on this machine. Before, each task recorded its
warnings with Python's ``catch_warnings``, one state for the whole worker process, so the tasks under way took each
other's notes: three photos warped ``--from exif`` at once said one photo's name on all three lines, or dropped two.

The reference is the same batch run without a scheduler; each photo's field of view is checked against exiftool's
FOV (its Composite tag, as tests/exif read it). The worker runs in this process (``processes=False``: the same
threads, the same ``warnings`` module state as a worker process) so that a barrier can hold the three tasks inside
their files until all three are there: the overlap is a state waited for, not a matter of timing.
"""

from __future__ import annotations

import re
import threading

import pytest

pytest.importorskip("distributed")

from lenslab.cli.main import main as lenslab  # noqa: E402
from tests.exif.exif_tools import exiftool, needs_exiftool, photo, shown_fov  # noqa: E402

pytestmark = [pytest.mark.slow, needs_exiftool]

FOCALS = {"wide.jpg": 24, "normal.jpg": 35, "tele.jpg": 85}  # 35 mm equivalents: a different field for each photo
W, H = 60, 40


def _notes(err: str) -> list[str]:
    return sorted(line for line in err.splitlines() if ": note: " in line)


def test_a_many_threaded_worker_says_each_photos_own_lens(tmp_path, capsys, monkeypatch):
    from distributed import Client, LocalCluster

    import lenslab.lenses.exif_view as exif_view

    photos = tmp_path / "photos"
    photos.mkdir()
    for name, f35 in FOCALS.items():
        photo(photos / name, W, H, "-FocalLength=4.25", f"-FocalLengthIn35mmFormat={f35}")  # (exiftool's FOV needs both)
    held = {"barrier": None}
    original = exif_view.exif_view

    def all_three_at_once(*args, **kwargs):  # each task waits here, inside its file, until every task is
        if held["barrier"] is not None:
            held["barrier"].wait(timeout=120)  # (a safety net only: three threads, three tasks, all start at once)
        return original(*args, **kwargs)

    monkeypatch.setattr(exif_view, "exif_view", all_three_at_once)
    cmd = ["warp", str(photos), "--from", "exif", "--to", "equirect", "--size", "32x16"]
    capsys.readouterr()
    assert lenslab(cmd + ["-o", str(tmp_path / "local")]) == 0
    local = _notes(capsys.readouterr().err)

    with LocalCluster(n_workers=1, threads_per_worker=len(FOCALS), processes=False, protocol="tcp://",
                      dashboard_address=None) as cluster, \
            Client(cluster, set_as_default=False) as client:
        held["barrier"] = threading.Barrier(len(FOCALS))
        assert lenslab(cmd + ["-o", str(tmp_path / "cluster"), "--scheduler", client.scheduler.address]) == 0
        held["barrier"] = None
    remote = _notes(capsys.readouterr().err)

    assert len(local) == len(FOCALS), local
    assert remote == local, remote
    for name in FOCALS:
        line, = (n for n in remote if f"{name}: source lens from the file's EXIF" in n)
        fov = float(re.search(r"perspective:fov=([0-9.e+-]+)", line).group(1))
        # 12 significant digits printed: within 1e-9 degrees of exiftool's FOV with its pi put right
        assert fov == pytest.approx(shown_fov(exiftool(photos / name, "FOV"), W, H), abs=1e-9), line


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
