"""The vector loops of the pyramid (``halve``: four doubles at a time for 1, 2, 3 and 4+ channels) and of the
footprint sides (``neighbour_secants``: eight pixels at a time) read nothing past their arrays, whatever the
width, height and channel count: each array is placed against a page the process may not touch (before it or
after it), so a read one float too far ends the child process. The values are the NumPy references' bits
(:mod:`lenslab.warp.kernels.pyramid_reference`, :func:`lenslab.warp.kernels.reference.neighbour_secants`), NaN,
inf and 1e30 included. Linux only (``mprotect``)."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="mprotect of an anonymous map")

CHILD = textwrap.dedent("""
    import ctypes, mmap
    import numpy as np
    from lenslab.warp.antialias import neighbour_secants
    from lenslab.warp.kernels import native, reference
    from lenslab.warp.kernels.pyramid_reference import halve as halve_reference

    libc = ctypes.CDLL(None, use_errno=True)
    keep = []

    def fenced(shape, dtype, before):
        # an array whose first byte follows (before) or whose last byte precedes a PROT_NONE page
        n = int(np.prod(shape)) * np.dtype(dtype).itemsize
        pages = -(-n // mmap.PAGESIZE) + 2
        m = mmap.mmap(-1, pages * mmap.PAGESIZE)
        base = ctypes.addressof(ctypes.c_char.from_buffer(m))
        keep.append(m)
        fence = base if before else base + (pages - 1) * mmap.PAGESIZE
        assert libc.mprotect(ctypes.c_void_p(fence), mmap.PAGESIZE, 0) == 0
        offset = mmap.PAGESIZE if before else (pages - 1) * mmap.PAGESIZE - n
        return np.frombuffer(m, dtype=dtype, count=int(np.prod(shape)), offset=offset).reshape(shape)

    rng = np.random.default_rng(5)
    k = native.kernels()
    for before in (False, True):
        for nc in range(1, 10):
            for h in (1, 2, 3, 5):
                for w in (1, 2, 3, 4, 5, 7, 8, 9, 16, 17):
                    src = fenced((h, w, nc), np.float32, before)
                    src[...] = rng.normal(size=src.shape)
                    src.flat[::7], src.flat[::11], src.flat[::13] = np.nan, np.inf, -1e30
                    out = fenced((h // 2, w // 2, nc), np.float32, before)
                    k.halve(src, out)
                    assert np.array_equal(out, halve_reference(src), equal_nan=True), (nc, h, w)
        for w in (1, 2, 3, 8, 9, 10, 11, 17, 25):
            for rows in (1, 2, 3, 4):
                xs, ys = fenced((rows, w), np.float32, before), fenced((rows, w), np.float32, before)
                vs = fenced((rows, w), np.bool_, before)
                xs[...], ys[...] = rng.normal(size=(rows, w)) * 50, rng.normal(size=(rows, w)) * 50
                vs[...] = True if rows > 2 else rng.uniform(size=(rows, w)) < 0.8
                foot, edge = fenced((rows, w, 1, 4), np.float32, before), fenced((rows, w, 1), np.bool_, before)
                neighbour_secants(xs, ys, vs, 0, 0.0, None, foot, edge, far=8.0)
                want, want_edge = reference.neighbour_secants(xs, ys, vs, 0, rows, 0.0, None)
                assert np.array_equal(foot[:, :, 0], want) and np.array_equal(edge[..., 0], want_edge), (w, rows)
    print("in bounds")
""")


def test_vector_loops_read_nothing_past_their_arrays():
    run = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True)
    assert run.returncode == 0, (run.returncode, run.stderr[-2000:])  # -11: a read past an array
    assert run.stdout.strip() == "in bounds"
