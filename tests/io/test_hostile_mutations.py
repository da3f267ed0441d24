"""Hypothesis-driven header and byte mutations of a valid file of every readable format of the registry
and of every calibration-file format, read in one subprocess per example under an address-space
limit: each read gives an image or a one-line lenslab error (LenslabError or OSError), never another
exception, a crash or a hang. A format added to either registry gets these mutations without a line
here, once it has a seed file (a writer in its record, or an entry in SEEDS below)."""

from __future__ import annotations

import functools
import struct
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lenslab.io as lio
from lenslab import calibfiles
from lenslab.io.registry import formats
from tests.hostile_run import read_many

#: seeds of the readable formats that have no writer
SEEDS = {"pbm": b"P4\n16 4\n" + bytes(range(8))}


def _video_seed(path):
    import av

    with av.open(str(path), "w") as c:
        s = c.add_stream("libx264", rate=24)
        s.width, s.height, s.pix_fmt = 32, 16, "yuv420p"
        for i in range(2):
            frame = av.VideoFrame.from_ndarray(np.full((16, 32, 3), 40 * i, np.uint8), format="rgb24")
            for packet in s.encode(frame):
                c.mux(packet)
        for packet in s.encode():
            c.mux(packet)


def _heif_seed(path):
    import pillow_heif

    img = (np.random.default_rng(2).random((24, 40, 4)) * 255).astype(np.uint8)
    pillow_heif.from_bytes("RGBA", (40, 24), img.tobytes()).save(str(path), quality=80)


def image_seeds(folder) -> dict[str, bytes]:
    """A small valid file of every readable format, by format name."""
    img = np.random.default_rng(1).random((24, 40, 3), dtype=np.float32) * 4
    out = {}
    for name, fmt in formats().items():
        if not fmt.readable:
            continue
        path = folder / f"seed{fmt.extensions[0]}"
        if fmt.writable:  # with an ICC profile where the format carries one, so mutations reach its parser
            from lenslab.io.colour.icc_build import profile

            icc = {"icc": profile("Display P3")} if "icc" in fmt.write_options else {}
            lio.write(path, img[..., :1] if 3 not in fmt.channels else img, format=name, **icc)
        elif fmt.kind == "video":
            _video_seed(path)
        elif name == "heif":
            _heif_seed(path)
        else:
            path.write_bytes(SEEDS[name])
        out[name] = path.read_bytes()
    return out


def camera_seeds(folder) -> dict[str, tuple[str, bytes]]:
    """A valid camera file of every calibration format: (suffix, bytes)."""
    from lenslab.lenses import make_lens

    lenses = {"opencv": "opencv:fx=300,fy=310,cx=319.5,cy=239.5,k1=-0.1,k2=0.01,p1=0.001,p2=0",
              "kalibr": "double-sphere:xi=-0.2,alpha=0.6,fx=200,fy=200,cx=320,cy=240",
              "colmap": "opencv:fx=300,fy=300,cx=319.5,cy=239.5,k1=-0.1",
              "ocam": "ocam:pol=-200 0 0.001,invpol=300 100 10,xc=240,yc=320",
              "toml": "fisheye:fov=190"}
    suffix = {"opencv": ".yaml", "kalibr": ".yaml", "colmap": ".txt", "ocam": ".txt", "toml": ".toml"}
    out = {}
    for name in calibfiles.FORMATS:
        path = folder / f"seed-{name}{suffix[name]}"
        calibfiles.write_lens(path, make_lens(lenses[name], (640, 480)), fmt=name, overwrite=True)
        out[name] = (suffix[name], path.read_bytes())
    return out


BIG = [0, 1, 0x7F, 0x80, 0xFF, 0x7FFF, 0xFFFF, 20000, 0x7FFFFFFF, 0xFFFFFFFF]
HOSTILE_WORDS = [b"inf", b"-inf", b"nan", b"1e308", b"-1", b"0", b"99999999999", b"[" * 200, b"&a", b"*a",
                 b"!!python/object:os.system", b"<!DOCTYPE x>", b"1e-320", b"18446744073709551616"]


@st.composite
def mutated(draw, data: bytes, text: bool = False) -> bytes:
    b = bytearray(data)
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["byte", "word", "cut", "insert"] + (["token"] * 3 if text else [])))
        head = min(len(b), 512)
        if op == "byte" and b:
            b[draw(st.integers(0, max(head - 1, 0)))] = draw(st.integers(0, 255))
        elif op == "word" and len(b) >= 4:
            at = draw(st.integers(0, max(head - 4, 0)))
            b[at:at + 4] = struct.pack(draw(st.sampled_from(["<I", ">I"])), draw(st.sampled_from(BIG)))
        elif op == "cut":
            b = b[:draw(st.integers(0, len(b)))]
        elif op == "insert":
            at = draw(st.integers(0, len(b)))
            b[at:at] = draw(st.binary(min_size=1, max_size=16))
        elif op == "token":
            words = list(__import__("re").finditer(rb"[-+0-9.eE]+|[A-Za-z_]+", bytes(b)))
            if words:
                m = draw(st.sampled_from(words))
                b[m.start():m.end()] = draw(st.sampled_from(HOSTILE_WORDS))
    return bytes(b)


def assert_read_or_refused(done, paths):
    bad = [line for line in done.stdout.splitlines() if line.startswith(("BAD", "LONG"))]
    assert done.returncode == 0, f"the reader crashed (status {done.returncode}) on " + (
        done.stdout.strip().splitlines() or ["?"])[-1] + "\n" + done.stderr[-800:]
    assert not bad, bad
    assert done.stdout.count("\nOK ") + done.stdout.count("\nREFUSED ") + done.stdout.startswith(("OK", "REFUSED")) \
        >= len(paths)


SETTINGS = settings(max_examples=4, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                           HealthCheck.data_too_large])
PER_FORMAT = 12  # mutated files of each format read by one subprocess


@functools.lru_cache(maxsize=1)
def seeds():
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        return image_seeds(Path(d)), camera_seeds(Path(d))


def test_every_readable_format_has_a_seed():
    images, cams = seeds()
    assert set(images) == {n for n, f in formats().items() if f.readable}
    assert set(cams) == set(calibfiles.FORMATS)
    for name, data in images.items():  # the seeds themselves are valid
        assert len(data) > 8, name


@SETTINGS
@given(data=st.data())
def test_mutated_images_are_read_or_refused_in_one_line(tmp_path_factory, data):
    images, _ = seeds()
    folder = tmp_path_factory.mktemp("mut")
    paths = []
    for name, seed in sorted(images.items()):
        ext = formats()[name].extensions[0]
        for i in range(PER_FORMAT):
            p = folder / f"{name}-{i}{ext}"
            p.write_bytes(data.draw(mutated(seed), label=p.name))
            paths.append(p)
    assert_read_or_refused(read_many("image", paths), paths)


@SETTINGS
@given(data=st.data())
def test_mutated_camera_files_are_read_or_refused_in_one_line(tmp_path_factory, data):
    _, cams = seeds()
    folder = tmp_path_factory.mktemp("mutcam")
    paths = []
    for name, (suffix, seed) in sorted(cams.items()):
        for i in range(PER_FORMAT):
            p = folder / f"{name}-{i}{suffix}"
            p.write_bytes(data.draw(mutated(seed, text=True), label=p.name))
            paths.append(p)
    assert_read_or_refused(read_many("camera", paths), paths)
