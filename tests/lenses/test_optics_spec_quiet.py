"""An ``optics`` lens prints its spec as a user types it: no ``tca=`` with nothing after it and no ``vignetting=none``
where neither effect was asked for (the values that mean 'none'), and what it prints parses back to the same lens.
The spec expected is the one typed here, with the base's own parameters spelled out."""

from __future__ import annotations

from lenslab.lenses.registry import make_lens


def test_no_empty_effects_in_the_spec():
    lens = make_lens("optics:base=fisheye,fov=200", (64, 64))
    assert lens.spec() == "optics:base=fisheye,fov=200,mapping=equidistant"
    assert make_lens(lens.spec(), (64, 64)) == lens


def test_effects_asked_for_are_printed():
    lens = make_lens("optics:tca=1.001/0.999,vignetting=cos4,base=fisheye,fov=180", (64, 64))
    assert "tca=1.001/0.999" in lens.spec() and "vignetting=cos4" in lens.spec()
    assert make_lens(lens.spec(), (64, 64)) == lens
