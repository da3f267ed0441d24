"""A clip probed by a job or command that ends before decoding it (an error after the probe, a probe alone) has its
file closed when that job or command ends, not when some later probe comes: the kernel's table of open descriptors
(``/proc/self/fd``) names the file no more. A probe and a decode in one command still open the file once.

Before, the probe's container stayed open until the next probe: one descriptor of the file after each of these."""

from __future__ import annotations

import os

import pytest

av = pytest.importorskip("av")

from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (an H.264 clip, by PyAV)

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="needs Linux's /proc/self/fd")


def _descriptors(path) -> int:
    """How many of this process's open descriptors the kernel lists for ``path``."""
    target, n = os.path.realpath(path), 0
    for fd in os.listdir("/proc/self/fd"):
        try:
            n += os.path.realpath(f"/proc/self/fd/{fd}") == target
        except OSError:  # (the descriptor listdir itself held, closed since)
            pass
    return n


@pytest.fixture
def clip(tmp_path):
    path = tmp_path / "clip.mp4"
    _clip(path, frames=3)
    return path


def test_a_job_that_probed_a_clip_and_failed_before_decoding_closes_it(clip, tmp_path):
    from lenslab.jobs.runner import execute
    from lenslab.jobs.warp import WarpJob

    # the job API takes a size the command line would refuse before probing: the encoder refuses it after the probe
    _, _, error, _ = execute(WarpJob(to="equirect", size=(7, 5)), str(clip), str(tmp_path / "out.mp4"))
    assert error is not None and "7 x 5" in error  # (the encoder's words for the size it refuses)
    assert _descriptors(clip) == 0
    assert not (tmp_path / "out.mp4").exists()


def test_a_command_that_only_probes_a_clip_closes_it(clip):
    from lenslab.io.video import probe_video
    from lenslab.jobs.funnel import run_command

    seen = []
    assert run_command("lenslab test", lambda: seen.append(probe_video(clip)) or 0) == 0
    assert (seen[0].width, seen[0].height) == (128, 64)  # what _clip wrote
    assert _descriptors(clip) == 0


def test_lenslab_info_leaves_no_descriptor_of_the_clip(clip, capsys):
    from lenslab.cli.main import main

    assert main(["info", str(clip)]) == 0
    assert "128 x 64" in capsys.readouterr().out
    assert _descriptors(clip) == 0


def test_a_clip_probed_and_warped_in_one_command_is_opened_once_and_closed(clip, tmp_path, monkeypatch):
    from lenslab.cli.main import main

    opens = []
    real = av.open
    monkeypatch.setattr(av, "open", lambda *a, **k: opens.append(str(a[0])) or real(*a, **k))
    out = tmp_path / "frames_%04d.exr"
    assert main(["warp", str(clip), "-o", str(out), "--to", "fisheye:fov=180", "--size", "32x32", "-q"]) == 0
    assert opens.count(str(clip)) == 1  # the budget's probe and the decoder share the container
    assert _descriptors(clip) == 0
    assert sorted(p.name for p in tmp_path.glob("frames_*.exr")) == [f"frames_{i:04d}.exr" for i in range(3)]


def test_a_batch_thread_releases_only_the_clip_its_own_job_probed(tmp_path):
    """A job ending on one thread of a local batch leaves the clip another thread has probed (and is about to decode)
    held for that decoder."""
    import threading

    from lenslab.io.video import opened, probe_video

    a, b = tmp_path / "a.mp4", tmp_path / "b.mp4"
    _clip(a)
    _clip(b, frames=2)
    other = threading.Thread(target=probe_video, args=(b,))
    other.start()
    other.join()
    opened.release()  # this thread probed nothing
    assert _descriptors(b) == 1
    opened.release(every=True)  # (the command's end)
    assert _descriptors(b) == 0
