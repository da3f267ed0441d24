"""Stereo frames (``stereo:sbs,...``, ``stereo:tb,...``) against Debian's ffmpeg ``v360`` with
``in_stereo``/``out_stereo``: each eye through its own half, both ways, within the tolerance of the other
v360 projections (``tests/warp/test_v360_ffmpeg.py``: ``TOL`` and ``EDGE`` are explained there)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.errors import LensError
from lenslab.lenses import make_lens
from tests.warp.test_v360_ffmpeg import assert_matches_ffmpeg, fragile, run_ffmpeg, run_lenslab, source_codes


def two_eyes(w: int, h: int, layout: str) -> np.ndarray:
    """A stereo frame whose eyes differ everywhere (the right eye is the left one's negative, shifted)."""
    left = source_codes(w, h)
    right = np.roll(255 - left, w // 3, axis=1)
    return np.concatenate([left, right], axis=1 if layout == "sbs" else 0)


def stereo_fragile(src, src_eye, dst, dst_eye, dst_layout):
    """:func:`fragile` per eye, laid out as the output frame is (2-D output: one eye)."""
    one = fragile(src, src_eye, dst, dst_eye)
    if dst_layout is None:
        return one
    return np.concatenate([one, one], axis=1 if dst_layout == "sbs" else 0)


def full(size, layout):
    w, h = size
    return (2 * w, h) if layout == "sbs" else (w, 2 * h) if layout == "tb" else (w, h)


#: (source base spec, v360 input, source eye size, source layout or None,
#:  output base spec, v360 output, output eye size, output layout or None)
CASES = [
    # VR180 (side by side half-equirect) into a side-by-side pair of flat views
    ("half-equirect", "hequirect", (64, 64), "sbs", "perspective:fov=90", "flat:h_fov=90:v_fov=90", (32, 32), "sbs"),
    # top-bottom 3D 360 into side-by-side half-equirect (VR180 from 360)
    ("equirect", "e", (128, 64), "tb", "half-equirect", "hequirect", (48, 48), "sbs"),
    # top-bottom 360 into a top-bottom cube map
    ("equirect", "e", (128, 64), "tb", "cubemap", "c3x2", (96, 64), "tb"),
    # a stereo fisheye pair as the source, out to top-bottom equirect
    ("fisheye:fov=190", "fisheye:ih_fov=190:iv_fov=190", (64, 64), "sbs", "equirect", "e", (96, 48), "tb"),
    # stereo in, mono out: v360 (and lenslab) take the left eye
    ("half-equirect", "hequirect", (64, 64), "sbs", "equirect", "e", (128, 64), None),
    ("equirect", "e", (128, 64), "tb", "perspective:fov=100", "flat:h_fov=100:v_fov=100", (48, 48), None),
    # mono in, stereo out: both eyes from the one source
    ("equirect", "e", (128, 64), None, "half-equirect", "hequirect", (48, 48), "sbs"),
    ("equirect", "e", (128, 64), None, "dual-fisheye:fov=190,front=right", "dfisheye:h_fov=190:v_fov=190", (96, 48), "tb"),
]


def spec(base, layout):
    if layout is None:
        return base
    name, _, rest = base.partition(":")
    return f"stereo:{layout},base={name}" + (f",{rest}" if rest else "")


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=[f"{c[3] or '2d'}-{c[1].split(':')[0]}-to-{c[7] or '2d'}-{c[5].split(':')[0]}"
                                              for c in CASES])
def test_stereo_matches_ffmpeg(tmp_path, case):
    s_base, s_v360, s_eye, s_layout, d_base, d_v360, d_eye, d_layout = case
    codes = two_eyes(*s_eye, s_layout) if s_layout else source_codes(*s_eye)
    opts = (f"input={s_v360}" + (f":in_stereo={s_layout}" if s_layout else "")
            + f":output={d_v360}" + (f":out_stereo={d_layout}" if d_layout else ""))
    theirs = run_ffmpeg(tmp_path, codes, opts, d_eye)  # v360's w, h are one eye's size
    ours, alpha = run_lenslab(tmp_path, codes, spec(s_base, s_layout), spec(d_base, d_layout), full(d_eye, d_layout))
    assert theirs.shape == ours.shape
    assert_matches_ffmpeg(ours, alpha, theirs, stereo_fragile(s_base, s_eye, d_base, d_eye, d_layout))


def test_each_eye_reads_only_its_half(tmp_path):
    """A constant left eye and a different constant right eye stay apart through a stereo warp, even
    where a filter tap reaches the middle of the frame (values are exact: no ffmpeg needed)."""
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    img = np.zeros((32, 128, 3), dtype=np.float32)
    img[:, :64] = 0.25
    img[:, 64:] = 4.0
    src = Camera.from_spec("stereo:sbs,base=equirect", (128, 32))
    dst = Camera.from_spec("stereo:tb,base=perspective,fov=120", (40, 80))
    for filt in ("bilinear", "bicubic", "lanczos"):
        out, alpha = warp(img, src, dst, filter=filt)
        assert np.all(alpha == 1.0)
        np.testing.assert_allclose(out[:40], 0.25, rtol=1e-6)
        np.testing.assert_allclose(out[40:], 4.0, rtol=1e-6)


def test_stereo_spec_and_errors():
    lens = make_lens("stereo:sbs,base=fisheye,fov=190", (256, 128))
    assert lens.spec() == "stereo:layout=sbs,base=fisheye,fov=190,mapping=equidistant"
    assert make_lens(lens.spec(), (256, 128)) == lens
    assert lens.base_lens.width == 128 and lens.base_lens.height == 128
    assert [p.eye for p in lens.pieces()] == [0, 1] and lens.pieces()[1].x0 == 128
    with pytest.raises(LensError, match="even"):
        make_lens("stereo:sbs,base=equirect", (127, 64))
    with pytest.raises(LensError, match="unknown parameter"):
        make_lens("stereo:tb,base=equirect,fov=90", (128, 128))
    with pytest.raises(LensError, match="layout"):
        make_lens("stereo:lr,base=equirect", (128, 128))


def test_st_map_pairs_the_eyes():
    """An ST map between stereo frames reads each output eye from its own source eye: the top eye's s
    stays in the left half of a side-by-side source, the bottom eye's in the right half, each the mono
    map of its eye moved by the eye's offset."""
    from lenslab.lenses import Camera
    from lenslab.stmap import st_map

    src = Camera.from_spec("stereo:sbs,base=equirect", (256, 64))
    dst = Camera.from_spec("stereo:tb,base=perspective,fov=100", (40, 80))
    st = st_map(src, dst)
    mono = st_map(Camera.from_spec("equirect", (128, 64)), Camera.from_spec("perspective:fov=100", (40, 40)))
    assert st[..., 3].all()
    np.testing.assert_allclose(st[:40, :, 0], mono[..., 0] * 0.5, atol=1e-7)
    np.testing.assert_allclose(st[40:, :, 0], mono[..., 0] * 0.5 + 0.5, atol=1e-7)
    np.testing.assert_allclose(st[:40, :, 1], mono[..., 1], atol=1e-7)
    np.testing.assert_allclose(st[40:, :, 1], mono[..., 1], atol=1e-7)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=60, deadline=None)
@given(base=st.sampled_from(["equirect", "half-equirect", "fisheye:fov=190", "cubemap", "perspective:fov=70"]),
       layout=st.sampled_from(["sbs", "tb"]), eye=st.integers(0, 1),
       fx=st.floats(0.0, 1.0, exclude_max=True), fy=st.floats(0.0, 1.0, exclude_max=True))
def test_each_eye_is_its_base(base, layout, eye, fx, fy):
    """A pixel of either eye sees what the base lens sees at the same place in its own frame."""
    size = (96, 64)
    full = (2 * size[0], size[1]) if layout == "sbs" else (size[0], 2 * size[1])
    name, _, rest = base.partition(":")
    stereo = make_lens(f"stereo:{layout},base={name}" + (f",{rest}" if rest else ""), full)
    mono = make_lens(base, size)
    local = np.array([[fx * size[0], fy * size[1]]])
    offset = np.array([[size[0] * eye, 0.0]]) if layout == "sbs" else np.array([[0.0, size[1] * eye]])
    d, ok = stereo.pixel_to_dir(local + offset)
    dm, okm = mono.pixel_to_dir(local)
    assert ok[0] == okm[0]
    # the eye's offset is added and taken off again: 1 ulp of a ~200 px coordinate, ~1e-15 in direction
    np.testing.assert_allclose(d, dm, rtol=0, atol=1e-13)
