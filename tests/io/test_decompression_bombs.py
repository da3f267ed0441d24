"""Decompression bombs (lenslab.bench.bombs): one valid flat-colour file under 1 MB for every registered
format that compresses; each is run through ``lenslab convert`` by tests/io/test_hostile_inputs.py (a
subprocess under an address-space limit, its peak memory against the 200 MB aim). Here: the registry
is covered, the bombs are what outside readers say they are, and the limit can be raised for a genuine
flat image."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

from lenslab.bench.bombs import BOMBS, RAW, write_bombs
from lenslab.io.registry import formats
from tests.hostile_run import run

oiio = pytest.importorskip("OpenImageIO")

#: lenslab.io.budget: a file under 1 MiB decodes to at most 128 MiB of float32
SMALL_FILE, BASE_BYTES = 1 << 20, 128 << 20


@pytest.fixture(scope="module")
def bombs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bombs")
    return folder, write_bombs(folder)


def test_every_registered_format_that_compresses_has_a_bomb():
    readable = {f.name for f in formats().values() if f.read is not None}
    assert readable == set(BOMBS) | set(RAW)


def _outside_size(path):
    """(width, height) as the format's reference reader sees it: PyAV for a clip, OpenImageIO otherwise."""
    if path.suffix == ".mp4":
        import av

        with av.open(str(path)) as clip:
            s = clip.streams.video[0]
            return s.width, s.height
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    inp.close()
    return spec.width, spec.height


def test_each_bomb_is_a_valid_file_under_1_mb_that_decodes_beyond_the_limit(bombs):
    folder, made = bombs
    for name, size in made.items():
        path = folder / name
        assert path.stat().st_size < SMALL_FILE, name
        assert _outside_size(path) == size, name
        assert size[0] * size[1] * 3 * 4 > BASE_BYTES, name  # float32 RGB


def test_the_radiance_bomb_decodes_with_the_limit_raised(bombs, tmp_path):
    """LENSLAB_BASE_BYTES (named in the refusal) admits a genuine flat image: the 0.93 MB Radiance file
    (3800 x 3800, 173 MB decoded) converts, and OpenImageIO reads black in the EXR written."""
    folder, _ = bombs
    out = tmp_path / "out.exr"
    env = dict(os.environ, LENSLAB_BASE_BYTES=str(200 << 20))
    done = run([sys.executable, "-m", "lenslab", "convert", str(folder / "bomb.hdr"), "--to", "exr", "-o", str(out),
                "-q"], env=env)
    assert done.returncode == 0, done.stderr
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    assert (spec.width, spec.height) == (3800, 3800)
    assert not pixels.any()  # RGBE (0, 0, 0, 0) is black (Ward, Graphics Gems II)
