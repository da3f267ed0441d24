"""Every warp filter in the registry (:data:`lenslab.filters.FILTERS`) reproduces its published kernel, and
the command line and the docs list exactly the registry's filters.

The kernels are transcribed here in float64 from their sources: Keys (1981), the cubic convolution kernel
with a = -1/2 (Catmull-Rom); Lanczos-3, ``sinc(t) sinc(t / 3)`` for ``|t| < 3`` (Turkowski, Graphics Gems
I); the tent and the box. The warp samples a source holding one bright column (an impulse in x) at
pinned offsets from it: what it returns there is the kernel's weight at that offset, divided by the sum
of the weights of the taps it read (1 for the tent and Catmull-Rom; Lanczos-3 is normalised). A
registered filter with no kernel transcribed here fails until one is added.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest

from lenslab.errors import WarpError
from lenslab.filters import FILTERS, filter_named
from lenslab.warp import warp_with_map


def box(t: float) -> float:
    return 1.0 if -0.5 <= t < 0.5 else 0.0  # ties go right: floor(x + 1/2)


def tent(t: float) -> float:
    return max(0.0, 1.0 - abs(t))


def keys(t: float, a: float = -0.5) -> float:
    """Keys (1981), eq. (15): the cubic convolution kernel; a = -1/2 is Catmull-Rom."""
    s = abs(t)
    if s <= 1:
        return (a + 2) * s ** 3 - (a + 3) * s ** 2 + 1
    if s < 2:
        return a * s ** 3 - 5 * a * s ** 2 + 8 * a * s - 4 * a
    return 0.0


def lanczos3(t: float) -> float:
    if t == 0:
        return 1.0
    if abs(t) >= 3:
        return 0.0
    return 3 * math.sin(math.pi * t) * math.sin(math.pi * t / 3) / (math.pi * t) ** 2


#: canonical filter name -> its published kernel w(t)
KERNELS = {"nearest": box, "bilinear": tent, "bicubic": keys, "lanczos": lanczos3}
#: offsets from the bright column, in source pixels: dyadic, so the map's float32 positions hold them exactly
OFFSETS = [-2.75, -2.5, -1.5, -0.5, -0.25, 0.0, 0.125, 0.5, 0.75, 1.25, 1.75, 2.25, 2.875]
COLUMN = 10


def test_the_transcribed_kernels_hold_their_published_values():
    # Catmull-Rom's half-pixel weights: 9/16 and -1/16 (Keys 1981, a = -1/2)
    assert keys(0.5) == 0.5625 and keys(1.5) == -0.0625 and keys(1.0) == 0.0 and keys(0.0) == 1.0
    # Lanczos-3 at 1/2: sinc(1/2) sinc(1/6) = (2 / pi) (3 / pi)
    assert lanczos3(0.5) == pytest.approx(6 / math.pi ** 2, rel=1e-15)
    assert lanczos3(0.5) == pytest.approx(0.6079271018540267, rel=1e-15)


@pytest.mark.parametrize("name", list(FILTERS))
def test_filter_reproduces_its_published_kernel(name):
    assert name in KERNELS, f"filter {name}: transcribe its published kernel into KERNELS"
    w, f = KERNELS[name], FILTERS[name]
    # the published kernel is zero beyond the radius the registry declares, and not just inside it
    assert all(w(s * (f.radius + k / 4)) == 0.0 for s in (-1, 1) for k in range(1, 8))
    assert w(-(f.radius - 1 / 8)) != 0.0
    src = np.zeros((5, 24), np.float32)
    src[:, COLUMN] = 1.0
    x = np.array(OFFSETS) + COLUMN + 0.5  # lenslab's continuous coordinates: pixel centres at +0.5
    xy = np.stack([x, np.full_like(x, 2.5)], axis=-1)[None]  # one output row, along the middle source row
    out, alpha = warp_with_map(src, xy, filter=name)
    want = [w(d) / (sum(w(d - n) for n in range(-6, 7)) if name == "lanczos" else 1.0) for d in OFFSETS]
    assert alpha.min() == 1.0
    # the weights are float64; the result is stored as float32 (half an ulp of values up to 1: 6e-8)
    np.testing.assert_allclose(out[0], want, rtol=0, atol=1e-7)


def test_other_names_and_unknown_names():
    assert filter_named("Catmull-Rom") == "bicubic" and filter_named("lanczos3") == "lanczos"
    for name, entry in ((e.name, e) for e in FILTERS.entries()):
        assert entry.references and entry.summary, f"filter {name} needs a summary and a reference"
    with pytest.raises(WarpError, match="unknown filter 'gauss'; choose one of nearest, bilinear, bicubic, lanczos"):
        filter_named("gauss")


def test_the_command_line_offers_the_registry_s_filters():
    from lenslab.cli import warp as cli_warp

    parser = argparse.ArgumentParser()
    cli_warp.add_arguments(parser)
    (action,) = [a for a in parser._actions if "--filter" in a.option_strings]
    assert list(action.choices) == list(FILTERS)
    for entry in FILTERS.entries():
        for alias in entry.aliases:  # another name is taken as the filter's own
            assert action.type(alias) == entry.name


def test_the_docs_list_every_filter():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "conventions.md").read_text(encoding="utf-8")
    listed = text.split("<!-- filters:start -->")[1].split("<!-- filters:end -->")[0]
    assert [line.split("`")[1] for line in listed.splitlines() if line.startswith("| `")] == list(FILTERS)
