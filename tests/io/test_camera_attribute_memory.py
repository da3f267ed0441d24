"""A camera TOML (a ``lenslab.camera`` EXR attribute, a ``.toml`` camera file) is read in memory bounded by its bytes:
a 10 MB string (a ``mirror`` of ten million letters) used to take 1.2 GB in the nesting check's string pattern, whose
alternation Python's regex engine backtracks through one stack frame per character."""

from __future__ import annotations

import sys

import numpy as np

from tests.hostile_run import run

#: the string's bytes
STRING = 10 << 20
#: peak resident memory allowed, MB: the interpreter with NumPy, OpenEXR and tomllib (about 60 MB here), and a few
#: copies of the 10 MB text (the attribute, the str, its UTF-8 bytes, tomllib's value, the message): 10 copies are
#: 105 MB; the failing pattern took 1,290 MB (/usr/bin/time -v on `lenslab info`)
BUDGET_MB = 60 + 10 * STRING / 1e6


def test_a_ten_megabyte_mirror_reads_in_memory_bounded_by_its_bytes(tmp_path):
    import OpenEXR

    path = tmp_path / "mirror.exr"
    camera = 'mirror = "' + "h" * STRING + '"\n[lens]\nmodel = "perspective"\nsize = [8, 4]\nfov = 60.0\n'
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "lenslab.camera": camera}
    OpenEXR.File(header, {"RGB": np.zeros((4, 8, 3), np.float32)}).write(str(path))
    code = ("import warnings, sys\nfrom lenslab.io import read\nwith warnings.catch_warnings(record=True) as w:\n"
            "    warnings.simplefilter('always')\n    _, meta = read(sys.argv[1])\n"
            "assert meta['camera'] is None\nprint(len(w), max(len(str(n.message)) for n in w))\n")
    done = run([sys.executable, "-c", code, str(path)])
    assert done.returncode == 0, done.stderr[-2000:]
    notes, longest = map(int, done.stdout.split())
    assert notes == 1 and longest < 600  # one note, of a line's length (docs/robustness.md)
    assert done.peak_mb < BUDGET_MB, f"{done.peak_mb:.0f} MB for a {STRING >> 20} MiB string"


def test_a_camera_attribute_not_read_is_one_note_naming_the_file_once(tmp_path):
    import subprocess

    import OpenEXR

    path = tmp_path / "flop.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "lenslab.camera": 'mirror = "x"\n[lens]\nmodel = "perspective"\nsize = [8, 4]\nfov = 60.0\n'}
    OpenEXR.File(header, {"RGB": np.zeros((4, 8, 3), np.float32)}).write(str(path))
    done = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(path), "-o", str(tmp_path / "o.exr")],
                          capture_output=True, text=True)
    notes = [line for line in done.stderr.splitlines() if "note:" in line]
    assert done.returncode == 0 and len(notes) == 1 and notes[0].count("flop.exr") == 1, done.stderr


def test_a_long_mirror_is_named_in_a_short_error():
    import pytest

    from lenslab.errors import LensError
    from lenslab.lenses.core.pose import Pose

    with pytest.raises(LensError) as caught:
        Pose.from_dict({"mirror": "hx" * 50_000})
    assert len(str(caught.value)) < 300 and "\n" not in str(caught.value)
