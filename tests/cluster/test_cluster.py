"""Batches and tiled renders on a Dask cluster: two worker processes of a LocalCluster on this machine.

The reference of every comparison is the same command run locally, without a scheduler: a cluster
run must give the same bytes (files) or the same float32 pixels (renders), not merely similar ones.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from tests.child_signals import default_stop_signals

pytest.importorskip("distributed")

from lenslab.cli.main import main as lenslab  # noqa: E402
from lenslab.io import read, write  # noqa: E402

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def scheduler():
    """The address of a scheduler with two single-threaded worker processes, no dashboard."""
    from lenslab.cluster.connect import local_cluster

    with local_cluster(workers=2, threads=1) as client:
        yield client.scheduler.address


def _frames(folder: Path, n: int, size=(64, 32), seed=0) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    paths = []
    for i in range(n):
        path = folder / f"frame{i:03d}.exr"
        write(path, (rng.random((size[1], size[0], 3), dtype=np.float32) * 8).astype(np.float32))
        paths.append(path)
    return paths


def _no_temporaries(folder: Path) -> None:
    left = [p.name for p in folder.iterdir() if ".tmp-" in p.name]
    assert not left, f"temporary files left behind: {left}"


def _same_bytes(a: Path, b: Path) -> None:
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_convert_and_warp_of_12_files_on_the_cluster_give_the_local_bytes(tmp_path, scheduler):
    _frames(tmp_path / "in", 12)
    for cmd in (["convert", str(tmp_path / "in"), "--to", "pfm"],
                ["warp", str(tmp_path / "in"), "--to", "fisheye:fov=180,mapping=equisolid", "--size", "32x32"]):
        local, remote = tmp_path / f"{cmd[0]}-local", tmp_path / f"{cmd[0]}-cluster"
        assert lenslab(cmd + ["-o", str(local), "-q"]) == 0
        assert lenslab(cmd + ["-o", str(remote), "-q", "--scheduler", scheduler]) == 0
        assert len(list(remote.iterdir())) == 12
        _same_bytes(local, remote)
        _no_temporaries(remote)


def test_the_scheduler_comes_from_the_environment_and_skip_existing_resumes(tmp_path, scheduler, monkeypatch):
    _frames(tmp_path / "in", 4)
    out = tmp_path / "out"
    out.mkdir()
    (out / "frame001.pfm").write_bytes(b"left alone")  # a stand-in for an output of an interrupted run
    monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", scheduler)
    assert lenslab(["convert", str(tmp_path / "in"), "--to", "pfm", "-o", str(out), "-q", "--skip-existing"]) == 0
    assert (out / "frame001.pfm").read_bytes() == b"left alone"
    assert sorted(p.name for p in out.iterdir()) == [f"frame{i:03d}.pfm" for i in range(4)]
    # without --skip-existing an existing output is a failure of that file only (no --overwrite)
    assert lenslab(["convert", str(tmp_path / "in"), "--to", "pfm", "-o", str(out), "-q"]) == 1


def test_a_corrupt_input_fails_alone(tmp_path, scheduler, capsys):
    frames = _frames(tmp_path / "in", 5)
    bad = tmp_path / "in" / "frame002.exr"
    bad.write_bytes(frames[0].read_bytes()[:200])  # a truncated EXR: the header survives, the pixels do not
    out = tmp_path / "out"
    status = lenslab(["convert", str(tmp_path / "in"), "--to", "exr", "-o", str(out), "--scheduler", scheduler])
    err = capsys.readouterr().err
    assert status == 1
    assert ": error: " in err and "frame002.exr" in err and "converted 4 of 5" in err
    assert sorted(p.name for p in out.iterdir()) == [f"frame{i:03d}.exr" for i in (0, 1, 3, 4)]
    for i in (0, 1, 3, 4):  # complete files: they read back as the source (half EXR: within half rounding)
        got, _ = read(out / f"frame{i:03d}.exr")
        want, _ = read(frames[i])
        np.testing.assert_allclose(got, want, rtol=2 ** -11)  # half has an 11-bit significand


def test_a_worker_killed_mid_batch_has_its_files_done_elsewhere(tmp_path, scheduler):
    from distributed import Client

    _frames(tmp_path / "in", 12, size=(512, 256))
    args = ["warp", str(tmp_path / "in"), "--to", "fisheye:fov=180", "--size", "256x256", "--samples", "9", "-q"]
    local = tmp_path / "local"
    assert lenslab(args + ["-o", str(local)]) == 0
    out = tmp_path / "out"
    result = {}
    run = threading.Thread(target=lambda: result.setdefault("status", lenslab(
        args + ["-o", str(out), "--scheduler", scheduler])))
    killed = None
    with Client(scheduler, set_as_default=False) as client:
        pids = client.run(os.getpid)
        run.start()
        deadline = time.monotonic() + 60
        while killed is None and time.monotonic() < deadline and run.is_alive():
            busy = [w for w, keys in client.processing().items() if keys]
            if busy and out.is_dir() and any(out.iterdir()):  # work done and work under way: kill a busy worker
                killed = busy[0]
                os.kill(pids[killed], signal.SIGKILL)
            time.sleep(0.02)
        run.join(120)
    assert killed is not None, "the batch ended before a worker could be killed"
    assert result.get("status") == 0
    _no_temporaries(out)
    _same_bytes(local, out)
    for path in out.iterdir():
        image, _ = read(path)
        assert image.shape == (256, 256, 4)


def test_tonemap_of_many_files_on_the_cluster_gives_the_local_bytes_and_each_file_alone(tmp_path, scheduler):
    frames = _frames(tmp_path / "in", 6)
    for i, name in enumerate(("a.png", "b.png")):  # the one-input command, run per file, is the reference
        assert lenslab(["tonemap", str(frames[i]), "-o", str(tmp_path / name), "--exposure", "auto", "-q"]) == 0
    cmd = ["tonemap", str(tmp_path / "in" / "*.exr"), "--exposure", "auto", "--curve", "aces", "-q"]
    local, remote = tmp_path / "local", tmp_path / "cluster"
    assert lenslab(cmd + ["-o", str(local)]) == 0
    assert lenslab(cmd + ["-o", str(remote), "--scheduler", scheduler]) == 0
    assert sorted(p.name for p in remote.iterdir()) == [f"frame{i:03d}.png" for i in range(6)]
    _same_bytes(local, remote)
    _no_temporaries(remote)
    one = tmp_path / "one"
    assert lenslab(["tonemap", str(frames[0]), str(frames[1]), "-o", str(one), "--exposure", "auto", "-q"]) == 0
    assert (one / "frame000.png").read_bytes() == (tmp_path / "a.png").read_bytes()
    assert (one / "frame001.png").read_bytes() == (tmp_path / "b.png").read_bytes()


def test_tonemap_with_a_corrupt_input_on_the_cluster_does_the_others_and_exits_1(tmp_path, scheduler, capsys):
    import cv2

    frames = _frames(tmp_path / "in", 4)
    (tmp_path / "in" / "frame002.exr").write_bytes(frames[0].read_bytes()[:200])  # header kept, pixels cut
    out = tmp_path / "out"
    status = lenslab(["tonemap", str(tmp_path / "in"), "-o", str(out), "--curve", "clamp", "--no-dither",
                      "--scheduler", scheduler])
    err = capsys.readouterr().err
    assert status == 1
    assert ": error: " in err and "frame002.exr" in err and "tone-mapped 3 of 4" in err
    assert sorted(p.name for p in out.iterdir()) == [f"frame{i:03d}.png" for i in (0, 1, 3)]
    for i in (0, 1, 3):  # OpenCV reads each file whole: clamp to 1, sRGB-encode, round to 8 bits
        got = cv2.imread(str(out / f"frame{i:03d}.png"), cv2.IMREAD_UNCHANGED)[..., ::-1]
        linear = np.clip(read(frames[i])[0].astype(np.float64), 0.0, 1.0)
        srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)  # IEC 61966-2-1
        # the codec's encoding may round the last half step the other way: one code value
        assert np.abs(got.astype(int) - np.round(srgb * 255).astype(int)).max() <= 1


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("command", [["convert", "--to", "pfm"], ["warp", "--to", "fisheye:fov=180"],
                                     ["tonemap"]])
def test_an_unreachable_scheduler_fails_the_start_and_makes_no_folder(tmp_path, command, capsys):
    _frames(tmp_path / "in", 2)
    address = f"tcp://127.0.0.1:{_free_port()}"
    out = tmp_path / "out"
    status = lenslab([command[0], str(tmp_path / "in"), "-o", str(out), *command[1:], "--scheduler", address,
                      "--scheduler-timeout", "2"])  # nothing listens: no need to wait 15 s
    err = capsys.readouterr().err
    assert status == 1  # a failed start (exit 1), not a usage error: the address may be right and the scheduler down
    assert err.count("\n") == 1 and address in err and "Traceback" not in err, err
    assert not out.exists()


def test_tiled_render_on_two_workers_equals_the_local_render_bit_for_bit(tmp_path, scheduler):
    from tracer.cli import main as tracer

    common = ["render", "--scene", "cornell", "--camera", "fisheye:fov=180,mapping=equisolid", "--size", "40x36",
              "--spp", "6", "--seed", "7", "-q"]
    assert tracer(common + ["-o", str(tmp_path / "local.exr")]) == 0
    assert tracer(common + ["-o", str(tmp_path / "tiled.exr"), "--scheduler", scheduler, "--tiles", "4"]) == 0
    local, _ = read(tmp_path / "local.exr")
    tiled, _ = read(tmp_path / "tiled.exr")
    assert local.dtype == tiled.dtype == np.float32
    assert np.array_equal(local, tiled)
    assert float(local.max()) > 0  # the image holds light, not zeros on both sides


@pytest.mark.parametrize("tiles", [1, 2, 3, 5, 100])
def test_any_tiling_renders_the_pixels_of_the_whole_image(tiles):
    from tracer.load import load_scene
    from tracer.rendering import render
    from tracer.tiles import tile_rows

    scene = load_scene("cornell")
    camera = scene.camera("equirect", (24, 20))
    whole = render(scene, camera, spp=5, seed=3, threads=2)
    ranges = tile_rows(camera, 5, tiles)
    assert ranges[0][0] == 0 and ranges[-1][1] == 20 and all(a[1] == b[0] for a, b in zip(ranges, ranges[1:]))
    parts = [render(scene, camera, spp=5, seed=3, threads=1, rows=r) for r in ranges]
    for name in ("image", "variance", "alpha"):
        assert np.array_equal(np.concatenate([getattr(p, name) for p in parts]), getattr(whole, name)), name


def _executing(client) -> int:
    return sum(client.run(lambda dask_worker: len(dask_worker.state.executing)).values())


@pytest.mark.parametrize("sig,code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_ctrl_c_cancels_the_batch_and_leaves_no_temporary_file(tmp_path, scheduler, sig, code):
    """Ctrl-C (or SIGTERM) during a cluster batch: the command ends at once, and no output appears after it
    has ended, not even from the tasks that were running at the signal. The workers are frozen (SIGSTOP)
    while a task runs, so the batch cannot finish before the signal; they go on after the command is gone."""
    import subprocess
    import sys

    from distributed import Client

    frames = _frames(tmp_path / "in", 40, size=(512, 256))
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "lenslab", "warp", str(tmp_path / "in"), "-o", str(out), "--to", "fisheye:fov=180",
           "--size", "512x512", "--samples", "16", "-q", "--scheduler", scheduler]
    guard = time.monotonic() + 300  # against a hang only: every wait below is for a state
    with Client(scheduler, set_as_default=False) as client:
        pids = list(client.run(os.getpid).values())
        proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, preexec_fn=default_stop_signals)
        frozen = False
        try:
            # under way: an output done and a task running on a worker
            while not (out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir())
                       and _executing(client)):
                assert proc.poll() is None, "the batch ended before it could be interrupted"
                assert time.monotonic() < guard
                time.sleep(0.01)
            for pid in pids:
                os.kill(pid, signal.SIGSTOP)
            frozen = True
            assert proc.poll() is None
            proc.send_signal(sig)
            _, err = proc.communicate(timeout=300)
            at_exit = {p.name for p in out.iterdir() if not p.name.startswith(".")}
        finally:
            if frozen:
                for pid in pids:
                    os.kill(pid, signal.SIGCONT)
            if proc.poll() is None:
                proc.kill()
        assert proc.returncode == code, err
        assert err.count("\n") == 1 and "interrupted" in err, err
        # the tasks under way at the signal finish on their workers: wait until none runs
        while _executing(client) or any(client.processing().values()):
            assert time.monotonic() < guard
            time.sleep(0.05)
    assert {p.name for p in out.iterdir() if not p.name.startswith(".")} == at_exit  # nothing written after
    assert len(at_exit) < len(frames)  # the rest was cancelled
    for name in at_exit:  # whatever was written is whole
        image, _ = read(out / name)
        assert image.shape == (512, 512, 4)
    # what the cancelled tasks left is named for the command, which has ended: the next batch into that
    # folder sweeps it (here a resume of the files already done, which has nothing else to do)
    done = [str(tmp_path / "in" / (Path(name).stem + ".exr")) for name in sorted(at_exit)]
    resumed = subprocess.run(cmd[:4] + done + cmd[5:] + ["--skip-existing"], capture_output=True, text=True,
                             timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    _no_temporaries(out)
    assert {p.name for p in out.iterdir()} == at_exit


def _trim_threshold() -> str | None:
    import os

    return os.environ.get("MALLOC_TRIM_THRESHOLD_")


def test_workers_start_without_the_trim_threshold_and_the_readme_recipe_does_the_same(scheduler, tmp_path):
    """lenslab's local workers, and workers started with the README's config file, keep the C library's
    own trimming (Dask's nanny would set MALLOC_TRIM_THRESHOLD_=65536 in each worker's environment)."""
    import re

    import dask
    from distributed import Client
    from distributed.nanny import _get_env_variables

    with Client(scheduler, set_as_default=False) as client:
        assert set(client.run(_trim_threshold).values()) == {None}
    text = (Path(__file__).parents[2] / "README.md").read_text()
    recipe = re.search(r"```yaml\n(distributed:\n.*?)```", text, re.S).group(1)
    (tmp_path / "lenslab.yaml").write_text(recipe)
    # Dask's defaults with the file on top, as `dask worker` reads its config folder
    config = dask.config.merge(dask.config.config, dask.config.collect(paths=[str(tmp_path)], env={}))
    with dask.config.set(config):
        env = _get_env_variables("distributed.nanny.pre-spawn-environ")  # what the nanny gives a worker
    assert "MALLOC_TRIM_THRESHOLD_" not in env and env["OMP_NUM_THREADS"] == "1"
    # without the file: Dask's default, for contrast
    assert _get_env_variables("distributed.nanny.pre-spawn-environ")["MALLOC_TRIM_THRESHOLD_"] == "65536"
