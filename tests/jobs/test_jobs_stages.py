"""The stages every job shares, checked against values computed here: exposure is 2**EV on colour only,
the encode stage passes only what a format declares, and every declared compression writes a file that
reads back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.io.registry import formats
from lenslab.jobs.stages import Look, develop, encode_options


def test_exposure_scales_colour_and_leaves_alpha(tmp_path):
    # premultiplied colour 0.25 at alpha 0.5: one stop doubles the colour, the coverage stays 0.5
    # (the convert command's copy of this stage multiplied alpha too)
    rgba = np.zeros((4, 4, 4), np.float32)
    rgba[..., :3], rgba[..., 3] = 0.25, 0.5
    write(tmp_path / "a.exr", rgba, pixel_type="float")
    assert main(["convert", str(tmp_path / "a.exr"), "--to", "exr", "-o", str(tmp_path / "b.exr"),
                 "--exposure", "1", "--pixel-type", "float", "-q"]) == 0
    out, _ = read(tmp_path / "b.exr")
    np.testing.assert_array_equal(out[..., :3], 0.5)
    np.testing.assert_array_equal(out[..., 3], 0.5)


def test_develop_leaves_scene_values_alone_for_float_outputs_and_tone_maps_display_outputs():
    image = np.full((2, 2, 3), 5.6, np.float32)  # Hable's white point over the exposure bias 2.0
    exr, png = formats()["exr"], formats()["png"]
    same, _ = develop(image, {"display_encoded": False}, exr, Look(tone="hable"))
    np.testing.assert_array_equal(same, image)
    white, _ = develop(image, {"display_encoded": False}, png, Look(tone="hable"))
    np.testing.assert_allclose(white, 1.0, atol=1e-6)  # f(2 * 5.6) / f(11.2) = 1


@pytest.mark.parametrize("name", sorted(n for n, f in formats().items() if f.writable))
def test_the_encode_stage_passes_only_what_a_format_declares(name):
    fmt = formats()[name]
    every = {"quality": 90, "bits": 16, "dither": True, "pixel_type": "float", "sample_type": "half",
             "compression": "zip"}
    opts = encode_options(fmt, {"camera": object()}, every, channels=2)
    assert set(opts) <= set(fmt.write_options) | ({"camera"} if fmt.camera else set())
    assert ("camera" in opts) == fmt.camera


@pytest.mark.parametrize("name,compression", [(n, c) for n, f in sorted(formats().items()) for c in f.compressions])
def test_every_declared_compression_writes_a_file_that_reads_back(tmp_path, name, compression):
    fmt = formats()[name]
    image = np.linspace(0.0, 1.0, 8 * 16 * 3, dtype=np.float32).reshape(8, 16, 3)
    path = tmp_path / f"x{fmt.extensions[0]}"
    opts = {"pixel_type": "float"} if "pixel_type" in fmt.write_options else {"sample_type": "float"}
    write(path, image, compression=compression, **opts)
    back, _ = read(path)
    # lossy codecs (DWA, B44, PXR24) keep float32 to within their stated error; the lossless ones exactly
    tol = {"dwaa": 0.05, "dwab": 0.05, "b44": 0.01, "b44a": 0.01, "pxr24": 1e-4}.get(compression, 0.0)
    np.testing.assert_allclose(back, image, atol=tol)


def test_a_new_batch_command_is_one_job_class(tmp_path):
    """A job is its options and run(input, output): the runner gives it threads, one-line failures and
    per-file notes without knowing what it does."""
    import argparse
    import warnings
    from dataclasses import dataclass
    from typing import ClassVar

    from lenslab.atomic import atomic_write_path
    from lenslab.jobs.job import Job
    from lenslab.jobs.runner import run_local

    @dataclass(frozen=True)
    class Upper(Job):
        command: ClassVar[str] = "upper"
        suffix: str = "!"

        def run(self, src, dst, progress=None):
            text = Path(src).read_text()
            if not text:
                raise ValueError("nothing to shout")
            if text.islower():
                warnings.warn("all lower case", UserWarning)
            with atomic_write_path(dst, overwrite=self.overwrite) as tmp:
                tmp.write_text(text.upper() + self.suffix)

    job = Upper.from_options(argparse.Namespace(suffix="?", overwrite=False, unrelated=1))
    assert job == Upper(suffix="?", overwrite=False)
    pairs = []
    for name, text in (("a", "hi"), ("b", ""), ("c", "Yo")):
        (tmp_path / f"{name}.txt").write_text(text)
        pairs.append((str(tmp_path / f"{name}.txt"), tmp_path / f"{name}.out"))
    results = run_local(job, pairs, jobs=2)
    assert [(r[0], r[2], r[3]) for r in results] == [(pairs[0][0], None, ["all lower case"]),
                                                     (pairs[1][0], "nothing to shout", []),
                                                     (pairs[2][0], None, [])]
    assert (tmp_path / "a.out").read_text() == "HI?" and (tmp_path / "c.out").read_text() == "YO?"
    assert not (tmp_path / "b.out").exists() and not list(tmp_path.glob(".*tmp-*"))
