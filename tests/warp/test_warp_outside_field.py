"""A photo placed in a panorama: the lattice cells wholly outside the photo's field are unseen without their
samples evaluated (``Lens.field``), and the map and the warp are the bits of evaluating every such cell.

The outside values: the equirect and the pinhole written in float64 here (``docs/conventions.md``), and the
poses' composition ``R_src^T R_dst``."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import Camera, Pose, make_lens
from lenslab.lenses.projections.fisheye import Fisheye
from lenslab.lenses.projections.perspective import Perspective
from lenslab.warp import warp
from lenslab.warp.maps import Mapper, sample_pattern


class NoFieldPerspective(Perspective):
    """The same pinhole (its compiled kernels too) without a field: every cell is evaluated as before."""

    def field(self):
        return None


class NoFieldFisheye(Fisheye):
    def field(self):
        return None


def unbounded(lens):
    other = {Perspective: NoFieldPerspective, Fisheye: NoFieldFisheye}[type(lens)]
    return other(lens.width, lens.height, **lens.param_values())


def equirect_dirs(xs, ys, w, h):
    """Output rays of a full-sphere equirect at pixel positions, float64 (x right, y up, z forward)."""
    lon = (2.0 * xs / w - 1.0) * np.pi
    lat = (1.0 - 2.0 * ys / h) * np.pi / 2
    return np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], axis=-1)


def pinhole_pixels(d, w, h, fov):
    """Where a pinhole of horizontal ``fov`` (square pixels) sees unit rays, and whether it does, float64:
    ``x = (dx/dz / t + 1) W/2``, ``y = (1 - dy/dz / t / (H/W)) H/2``, seen for ``dz > 0`` inside the frame."""
    t = np.tan(np.radians(fov) / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = (d[..., 0] / d[..., 2] / t + 1.0) * w / 2
        y = (1.0 - d[..., 1] / d[..., 2] / t / (h / w)) * h / 2
    seen = (d[..., 2] > 0) & (x >= 0) & (x <= w) & (y >= 0) & (y <= h)
    edge = np.minimum(np.minimum(np.abs(x), np.abs(x - w)), np.minimum(np.abs(y), np.abs(y - h)))
    return x, y, seen, np.where(d[..., 2] > 0, edge, np.inf)


def band(mapper, offsets):
    return mapper.map_band(0, mapper.height, offsets)


poses = st.tuples(st.floats(-180, 180), st.floats(-90, 90), st.floats(-180, 180))


@settings(max_examples=25, deadline=None)
@given(poses, st.floats(5.0, 150.0))
def test_cells_far_outside_the_photo_are_unseen_unevaluated(ypr, fov):
    """Every cell whose centre's ray is 15 degrees or more beyond the photo's half diagonal field (the cell and
    its stencil span under 9 degrees at 720 x 360) is marked unseen (-1): before, such cells were computed
    sample by sample (0)."""
    src = Camera(make_lens(f"perspective:fov={fov}", (320, 240)), Pose.from_ypr(*ypr))
    dst = Camera(make_lens("equirect", (720, 360)))
    state = Mapper(src, dst).lattice[1]
    s = 8
    cy, cx = np.mgrid[0:state.shape[0], 0:state.shape[1]]
    d = equirect_dirs((cx + 0.5) * s, (cy + 0.5) * s, 720, 360) @ (src.pose.rotation.T @ dst.pose.rotation).T
    half_diagonal = np.degrees(np.arctan(np.tan(np.radians(fov) / 2) * np.hypot(1.0, 240 / 320)))
    far = np.degrees(np.arccos(np.clip(d[..., 2], -1, 1))) > half_diagonal + 15.0
    far[[0, -1], :] = False  # the stencils of the first and last cells leave the image (no output ray there)
    far[:, [0, -1]] = False
    assert far.sum() > 0.3 * far.size
    assert (state[far] == -1).all()


@settings(max_examples=20, deadline=None)
@given(poses, st.floats(5.0, 170.0), st.sampled_from([1, 4]))
def test_map_is_the_map_of_every_cell_evaluated(ypr, fov, samples):
    """The band's map (positions and validity) has the bits of the same lens without a field."""
    lens = make_lens(f"perspective:fov={fov}", (300, 200))
    dst = Camera(make_lens("equirect", (640, 320)))
    pose = Pose.from_ypr(*ypr)
    new = band(Mapper(Camera(lens, pose), dst), sample_pattern(samples))
    old = band(Mapper(Camera(unbounded(lens), pose), dst), sample_pattern(samples))
    for a, b in ((new.xs, old.xs), (new.ys, old.ys), (new.valid, old.valid)):
        assert a.tobytes() == b.tobytes()


@settings(max_examples=15, deadline=None)
@given(poses, st.floats(60.0, 250.0), st.sampled_from(["equidistant", "equisolid"]))
def test_fisheye_map_is_the_map_of_every_cell_evaluated(ypr, fov, mapping):
    lens = make_lens(f"fisheye:fov={fov},mapping={mapping}", (300, 300))
    dst = Camera(make_lens("equirect", (640, 320)))
    pose = Pose.from_ypr(*ypr)
    new = band(Mapper(Camera(lens, pose), dst), sample_pattern(1))
    old = band(Mapper(Camera(unbounded(lens), pose), dst), sample_pattern(1))
    for a, b in ((new.xs, old.xs), (new.ys, old.ys), (new.valid, old.valid)):
        assert a.tobytes() == b.tobytes()


CASES = {  # source lens, its size, its pose (yaw, pitch, roll), output lens, output size, warp options
    "photo": ("perspective:fov=71.5", (408, 307), (0, 0, 0), "equirect", (708, 354), {}),
    "across the seam": ("perspective:fov=71.5", (408, 307), (170, 5, 0), "equirect", (708, 354), {}),
    "over the pole": ("perspective:fov=71.5", (408, 307), (30, 85, 10), "equirect", (708, 354), {"samples": 4}),
    "fisheye 200": ("fisheye:fov=200", (400, 400), (60, 10, 0), "equirect", (708, 354), {}),
    "stereo output": ("perspective:fov=71.5", (300, 200), (0, 0, 0), "stereo:layout=tb", (600, 600), {}),
    "tiled output": ("perspective:fov=71.5", (300, 200), (45, 0, 0), "tiled:grid=2x2", (512, 512), {}),
    "jittered": ("perspective:fov=40", (300, 200), (-100, -30, 0), "equirect", (708, 354), {"samples": 2, "seed": 5}),
}


@pytest.mark.parametrize("name", list(CASES))
def test_warp_has_the_bits_of_every_cell_evaluated(name):
    spec, size, ypr, out_spec, out_size, options = CASES[name]
    image = np.random.default_rng(7).random((size[1], size[0], 3), dtype=np.float32)
    lens = make_lens(spec, size)
    dst = Camera(make_lens(out_spec, out_size))
    new = warp(image, Camera(lens, Pose.from_ypr(*ypr)), dst, **options)
    old = warp(image, Camera(unbounded(lens), Pose.from_ypr(*ypr)), dst, **options)
    assert new[1].any() and not new[1].all()  # the photo is somewhere in the output, not everywhere
    for a, b in zip(new, old):
        assert a.tobytes() == b.tobytes()


@settings(max_examples=15, deadline=None)
@given(poses, st.floats(20.0, 120.0))
def test_unseen_is_exactly_unseen_and_seen_reads_the_formula(ypr, fov):
    """Coverage is 0 exactly where the float64 formula says the photo does not see the output pixel's ray, and 1
    where it does (pixels within 0.01 px of the frame's edge excepted: the lattice may round either way there).
    At seen pixels the map reads the formula's position within 5e-3 px: the lattice's checked tolerance (2e-3 px)
    plus float32's rounding of a position under 512 px (3e-5 px)."""
    w, h = 320, 240
    src = Camera(make_lens(f"perspective:fov={fov}", (w, h)), Pose.from_ypr(*ypr))
    dst = Camera(make_lens("equirect", (720, 360)))
    image = np.ones((h, w, 1), dtype=np.float32)
    _, coverage = warp(image, src, dst)
    m = band(Mapper(src, dst), sample_pattern(1))
    ys, xs = np.mgrid[0:360, 0:720] + 0.5
    d = equirect_dirs(xs, ys, 720, 360) @ (src.pose.rotation.T @ dst.pose.rotation).T
    x, y, seen, edge = pinhole_pixels(d, w, h, fov)
    sure = edge > 0.01
    assert (coverage[sure & ~seen] == 0).all()
    assert (coverage[sure & seen] == 1).all()
    assert (m.valid[..., 0] == seen)[sure].all()
    pick = np.flatnonzero((sure & seen).reshape(-1))
    assert len(pick) > 0
    pick = pick[np.linspace(0, len(pick) - 1, 7).astype(int)]
    got_x, got_y = m.xs[..., 0].reshape(-1)[pick] + 0.5, m.ys[..., 0].reshape(-1)[pick] + 0.5
    assert np.abs(got_x - x.reshape(-1)[pick]).max() < 5e-3
    assert np.abs(got_y - y.reshape(-1)[pick]).max() < 5e-3
