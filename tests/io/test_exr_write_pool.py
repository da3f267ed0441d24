"""An EXR is compressed on OpenEXR's own thread pool (``lenslab.io.exr.THREADS``): the Python bindings write with
the library's global pool, whatever count the ``File`` is given, so the writer sizes that pool. The file is the
same whatever the count (OpenEXR writes its chunks in order), and holds the image as OpenImageIO reads it: the
float16 rounding of the float32 values (NumPy's, IEEE 754 round to nearest even: exact equality).
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

oiio = pytest.importorskip("OpenImageIO")

WRITE = """
import json, sys
import numpy as np
import OpenEXR
import lenslab.io.exr as exr
from lenslab.io.exr import write_exr
before = OpenEXR.global_thread_count()
exr.THREADS = int(sys.argv[2])
image = np.load(sys.argv[1])
write_exr(sys.argv[3], image)
print(json.dumps({"before": before, "pool": OpenEXR.global_thread_count()}))
"""


def _write(src, threads: int, out) -> dict:
    done = subprocess.run([sys.executable, "-c", WRITE, str(src), str(threads), str(out)], capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_exr_compression_runs_on_a_pool_of_the_given_size_and_writes_the_same_file(tmp_path):
    rng = np.random.default_rng(3)
    image = (rng.random((300, 257, 4), dtype=np.float32) * np.linspace(0, 4, 257, dtype=np.float32)[None, :, None])
    np.save(tmp_path / "in.npy", image)
    pooled = _write(tmp_path / "in.npy", 2, tmp_path / "two.exr")
    alone = _write(tmp_path / "in.npy", 0, tmp_path / "none.exr")
    assert pooled == {"before": 0, "pool": 2}  # the library's default is no pool
    assert alone["pool"] == 0
    assert (tmp_path / "two.exr").read_bytes() == (tmp_path / "none.exr").read_bytes()
    read = oiio.ImageInput.open(str(tmp_path / "two.exr"))
    got = read.read_image(oiio.HALF)
    read.close()
    assert np.array_equal(np.asarray(got), image.astype(np.float16))
