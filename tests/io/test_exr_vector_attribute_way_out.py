"""A valid EXR whose header holds a large float vector (a 1.5 MB ``floatvector``: a LUT of 393216 floats, which
OpenEXR writes and reads back whole) is refused by default in one line that says the file's size of it and how to read
it (LENSLAB_EXR_VECTOR_BYTES), not that the file is damaged; with that variable raised lenslab reads the vector as
OpenEXR does.

Outside values: OpenEXR's own reading of the file's header (the vector's 393216 values) and exit code 1 for a failed
input (the product's rule)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

FLOATS = 393216  # 1.5 MB, over the default 1 MiB


@pytest.fixture(scope="module")
def lut_exr(tmp_path_factory):
    import OpenEXR

    path = tmp_path_factory.mktemp("lut") / "lut.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "lut": [i / FLOATS for i in range(FLOATS)]}
    OpenEXR.File(header, {"RGB": np.full((4, 8, 3), 0.25, np.float32)}).write(str(path))
    with OpenEXR.File(str(path)) as f:
        assert len(f.header()["lut"]) == FLOATS
    return path


def _lenslab(*args, env=None):
    return subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, env={**os.environ, **(env or {})})


def test_a_large_vector_is_refused_naming_the_way_to_read_it(lut_exr):
    done = _lenslab("info", lut_exr)
    assert done.returncode == 1
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and "'lut'" in lines[0] and f"{4 * FLOATS:,} bytes" in lines[0], lines
    assert "LENSLAB_EXR_VECTOR_BYTES" in lines[0] and "damaged" not in lines[0]


def test_the_variable_reads_it_as_openexr_does(lut_exr):
    import OpenEXR

    with OpenEXR.File(str(lut_exr)) as f:
        expected = list(f.header()["lut"])
    code = ("import sys, lenslab.io as lio; a = lio.read(__import__('pathlib').Path(sys.argv[1]))[1]['attributes'];"
            "print(repr(list(a['lut'])))")
    done = subprocess.run([sys.executable, "-c", code, str(lut_exr)], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "LENSLAB_EXR_VECTOR_BYTES": str(2 << 20)})
    assert done.returncode == 0, done.stderr[-400:]
    assert eval(done.stdout) == expected  # noqa: S307  (the repr of a list of floats printed just above)
