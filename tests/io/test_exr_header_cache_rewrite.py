"""The EXR header kept from one parse (:func:`lenslab.io.exr.chunks.parse_header`) is never the header of a
file written since, even where the file system cannot tell: a file rewritten in place with as many bytes,
on a file system whose times are coarse (FAT keeps 2 s, network and older kernels a clock tick) or an
inode reused by a file written at the same path, has the same device, inode, size and times as before.
Expected values: OpenEXR's own reading of the file as it is now."""

from __future__ import annotations

import os
import threading
import types

import numpy as np
import OpenEXR

from lenslab.io.exr import chunks
from lenslab.io.registry import formats


def _write(path, names, window=((0, 0), (15, 7))):
    """An uncompressed float EXR (its size depends on its window and on its names' lengths only)."""
    (x0, y0), (x1, y1) = window
    planes = {n: np.full((y1 - y0 + 1, x1 - x0 + 1), i + 1, np.float32) for i, n in enumerate(names)}
    OpenEXR.File({"compression": OpenEXR.NO_COMPRESSION, "type": OpenEXR.scanlineimage, "dataWindow": window,
                  "displayWindow": ((0, 0), (15, 7))}, planes).write(str(path))


def _openexr_names(path):
    return [c.name for c in OpenEXR.File(str(path), header_only=True).parts[0].header["channels"]]


def _frozen_times(monkeypatch):
    """The file system of the test as one with coarse times: every file's times and inode read as fixed."""
    def fstat(fd):
        st = os.fstat(fd)
        return types.SimpleNamespace(st_dev=st.st_dev, st_ino=1, st_size=st.st_size, st_mtime_ns=10**18,
                                     st_ctime_ns=10**18)

    monkeypatch.setattr(chunks, "os", types.SimpleNamespace(fstat=fstat, path=os.path))


def test_a_file_rewritten_in_place_with_as_many_bytes_is_parsed_anew(tmp_path, monkeypatch):
    _frozen_times(monkeypatch)
    path = tmp_path / "shot.exr"
    _write(path, ["R", "G", "B"])
    assert chunks.parse_header(path).parts[0]["channel_names"] == _openexr_names(path) == ["B", "G", "R"]
    size = path.stat().st_size
    _write(path, ["X", "Y", "Z"])  # the same byte count, other channels
    assert path.stat().st_size == size
    want = _openexr_names(path)
    assert want == ["X", "Y", "Z"]
    assert chunks.parse_header(path).parts[0]["channel_names"] == want
    assert formats()["exr"].channel_names(path) == want  # a command's channel check before its job
    # and the pixels' windows: a file with another data window but the same size
    _write(path, ["X", "Y", "Z"], window=((1, 0), (16, 7)))
    assert path.stat().st_size == size
    assert chunks.parse_header(path).parts[0]["dataWindow"] == (1, 0, 16, 7)


def test_an_unchanged_file_is_still_parsed_once(tmp_path, monkeypatch):
    path = tmp_path / "shot.exr"
    _write(path, ["R", "G", "B"])
    first = chunks.parse_header(path)
    calls = []
    headers = chunks._headers
    monkeypatch.setattr(chunks, "_headers", lambda f, size: calls.append(1) or headers(f, size))
    assert chunks.parse_header(path) is first
    assert calls == []


def test_threads_asking_about_one_file_get_its_header(tmp_path):
    """Eight threads parse the same file (and each a file of its own) at once: each answer is OpenEXR's."""
    shared = tmp_path / "shared.exr"
    _write(shared, ["R", "G", "B"])
    own = [tmp_path / f"own{i}.exr" for i in range(8)]
    for i, p in enumerate(own):
        _write(p, [f"c{i}", "Z"])
    want = {str(p): _openexr_names(p) for p in [shared, *own]}
    got, start = {}, threading.Barrier(8)

    def run(i):
        start.wait()
        for _ in range(20):
            for p in (shared, own[i]):
                got.setdefault(str(p), []).append(chunks.parse_header(p).parts[0]["channel_names"])

    threads = [threading.Thread(target=run, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for p, answers in got.items():
        assert all(a == want[p] for a in answers), p
