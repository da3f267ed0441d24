"""Bad input: damaged, truncated, hostile and mislabelled files give one clear FormatError
(OS problems stay OSError), never a crash, a hang, a huge allocation or a partial output file."""

from __future__ import annotations

import os
import tempfile
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lenslab.io as lio
from lenslab.errors import FormatError

FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _valid_files() -> dict[str, bytes]:
    """One small valid file per format, as bytes."""
    rng = np.random.default_rng(0)
    img = rng.random((6, 7, 3)).astype(np.float32)
    out = {}
    with tempfile.TemporaryDirectory() as d:
        for name, opts in (("a.exr", {}), ("b.exr", {"pixel_type": "float", "compression": "piz"}),
                           ("a.pfm", {}), ("a.ppm", {}), ("b.ppm", {"bits": 16}), ("c.ppm", {"ascii": True}),
                           ("a.pgm", {}), ("a.png", {}), ("a.jpg", {})):
            data = img[..., :1] if name.endswith(".pgm") else img
            out[name] = lio.write(Path(d) / name, data, **opts).read_bytes()
    out["a.pbm"] = b"P4\n7 6\n" + bytes(range(6))
    out["b.pbm"] = b"P1\n# comment\n3 2\n0 1 0\n1 1 0\n"
    return out


VALID = _valid_files()


def _read_bytes(data: bytes, suffix: str = ".img"):
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / f"f{suffix}"
        p.write_bytes(data)
        return lio.read(p)


def check_only_format_error(data: bytes, suffix: str = ".img") -> None:
    try:
        img, meta = _read_bytes(data, suffix)
    except FormatError as exc:
        assert str(exc)  # a message, naming the file
        assert "f" + suffix in str(exc)
        return
    assert img.dtype == np.float32 and img.ndim == 3 and img.shape[2] >= 1  # damage it could survive


@FUZZ
@given(name=st.sampled_from(sorted(VALID)), cut=st.floats(0.0, 1.0, exclude_max=True))
def test_truncated_files_raise_format_error(name, cut):
    data = VALID[name]
    check_only_format_error(data[: int(len(data) * cut)])


@FUZZ
@given(name=st.sampled_from(sorted(VALID)), flips=st.lists(st.tuples(st.floats(0, 1, exclude_max=True),
                                                                    st.integers(0, 7)), min_size=1, max_size=4))
def test_bit_flips_raise_only_format_error(name, flips):
    data = bytearray(VALID[name])
    for where, bit in flips:
        data[int(where * len(data))] ^= 1 << bit
    check_only_format_error(bytes(data))


@FUZZ
@given(magic=st.sampled_from([b"P1", b"P2", b"P3", b"P4", b"P5", b"P6", b"PF", b"Pf", b"PF4", b"v/1\x01",
                              b"\x89PNG\r\n\x1a\n", b"\xff\xd8\xff"]),
       rest=st.binary(max_size=200))
def test_random_payload_after_magic(magic, rest):
    check_only_format_error(magic + rest)


@FUZZ
@given(magic=st.sampled_from([b"P2", b"P3", b"P5", b"P6", b"PF", b"Pf"]),
       fields=st.lists(st.one_of(st.integers(-10, 70000), st.text("0123456789-+.eE#x ", max_size=25)),
                       min_size=0, max_size=4),
       tail=st.binary(max_size=64))
def test_random_headers(magic, fields, tail):
    header = magic + b"\n" + b" ".join(str(f).encode() for f in fields) + b"\n"
    check_only_format_error(header + tail)


@pytest.mark.parametrize("data, match", [
    (b"P5\n4 4\n0\n" + bytes(16), "maxval 0"),
    (b"P5\n4 4\n65536\n" + bytes(32), "maxval 65536"),
    (b"P6\n-4 4\n255\n" + bytes(48), "expected the width"),
    (b"P1\n12345678901234567890 1\n0\n", "more than 9 digits"),
    (b"P5\n65000 65000\n255\n", "beyond the limit"),
    (b"P6\n4000 4000\n255\n" + bytes(100), "truncated"),
    (b"P2\n3 3\n255\n1 2 3\n", "truncated"),
    (b"P2\n2 1\n10\n5 11\n", "exceeds the maxval"),
    (b"P3\n1 1\n255\n1 x 3\n", "not a decimal"),
    (b"P5 2 2 255", "one white-space"),
    (b"PF4\n2 2\n-1.0\n" + bytes(64), "PF4"),
    (b"PF\n2 2\n0\n" + bytes(48), "non-zero"),
    (b"PF\n2 2\nnan\n" + bytes(48), "non-zero"),
    (b"PF\n2 2\n-1.0\n" + bytes(47), "truncated"),
    (b"Pf\n9999 9999\n-1.0\n", "truncated"),
    (b"PF\n2000000 2\n-1.0\n", "beyond the limit"),
    (b"GIF89a....", "not a recognised image"),
    (b"", "empty"),
    (b"v/1\x01" + bytes(40), "OpenEXR"),
    (b"\x89PNG\r\n\x1a\n" + bytes(4) + b"IHDR" + (70000).to_bytes(4, "big") * 2, "beyond the limit"),
])
def test_specific_bad_files(tmp_path, data, match):
    p = tmp_path / "bad.ppm"  # the name lies for most of them: the magic decides
    p.write_bytes(data)
    with pytest.raises(FormatError, match=match) as info:
        lio.read(p)
    assert str(p) in str(info.value)


def test_bombs_refused_before_allocating(tmp_path):
    bombs = {"p5.pgm": b"P5\n65000 65000\n255\n", "p4.pbm": b"P4\n65000 65000\n" + bytes(1000),
             "p2.pgm": b"P2\n65000 65000\n255\n" + b"1 " * 1000, "pf.pfm": b"PF\n65000 65000\n-1.0\n" + bytes(100),
             "p6.ppm": b"P6\n30000 30000\n65535\n" + bytes(1000)}
    for name, data in bombs.items():
        (tmp_path / name).write_bytes(data)
        tracemalloc.start()
        with pytest.raises(FormatError):
            lio.read(tmp_path / name)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert peak < 8 << 20, name  # a refusal costs kilobytes, not the gigabytes the header claims


def test_deep_exr_read_flattened(shared_data):  # (their values: tests/io/test_exr_deep_oiio.py)
    import warnings

    for rel, samples in (("v2/LowResLeftView/Trunks.exr", 49152), ("v2/Stereo/Trunks.exr", 172743)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the note that the first of two parts is read
            img, meta = lio.read(shared_data / "formats/openexr-images" / rel)
        assert meta["channels"] == ["R", "G", "B", "A"] and meta["deep"]["samples"] == samples


def test_os_errors_stay_os_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        lio.read(tmp_path / "missing.exr")
    with pytest.raises(IsADirectoryError):
        lio.read(tmp_path)
    img = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(FileNotFoundError):
        lio.write(tmp_path / "no" / "such" / "dir.exr", img)
    (tmp_path / "file").write_bytes(b"x")
    with pytest.raises(OSError):
        lio.write(tmp_path / "file" / "below.exr", img)  # a file where a directory is expected
    with pytest.raises(IsADirectoryError):
        lio.write(tmp_path, img, format="exr")
    assert sorted(os.listdir(tmp_path)) == ["file"]  # nothing partial left anywhere


def test_unwritable_directory(tmp_path):
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o500)
    try:
        if os.access(d, os.W_OK):  # the super-user writes anyway; the refusal is then the OS's to make
            lio.write(d / "a.pfm", np.zeros((2, 2, 3), np.float32))
            assert (d / "a.pfm").exists()
        else:
            with pytest.raises(PermissionError):
                lio.write(d / "a.pfm", np.zeros((2, 2, 3), np.float32))
            assert os.listdir(d) == []
    finally:
        d.chmod(0o700)


def test_selector_on_non_exr_and_bad_arrays(tmp_path):
    p = lio.write(tmp_path / "a.pfm", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(FormatError, match="only applies to EXR"):
        lio.read(f"{p}:left")
    for bad in (np.zeros((2, 2, 5)), np.zeros((0, 3, 3)), np.zeros(5), np.array([["a"]])):
        with pytest.raises(FormatError):
            lio.write(tmp_path / "x.exr", bad)
    assert sorted(os.listdir(tmp_path)) == ["a.pfm"]
