"""The direction-encoding check: a panorama whose pixels hold their own ray (x, y, z as colours),
warped into each lens model, must give each output pixel its own ray, ``pixel_to_dir`` of that
pixel's centre; and an image holding each pixel's ray in a model, read back into a panorama, must give
the panorama's rays. A wrong formula, a mirrored face or a half-pixel slip shows as an angle of a
pixel or more; what is left is the bilinear interpolation of a smooth field."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp import warp

PANO = (1024, 512)
#: bilinear interpolation of unit vectors sampled every d = 2 pi / 1024 rad errs by at most
#: d^2 / 8 per axis (second derivatives <= 1): 1e-5 rad over both axes, plus float32 colours (6e-8)
TOL = 2e-5

CASES = [
    ("equirect", (256, 128)),
    ("perspective:fov=100", (160, 120)),
    ("perspective:dfov=100", (192, 128)),
    ("fisheye:fov=200,mapping=equisolid", (128, 128)),
    ("fisheye:fov=180,mapping=stereographic", (128, 128)),
    ("fisheye:fov=160,mapping=orthographic", (128, 128)),
    ("fisheye:dfov=180", (192, 128)),  # full frame on 3:2: the corners are 90 degrees off axis
    ("fisheye:vfov=150,mapping=equisolid,cx=0.1,cy=-0.05", (192, 128)),
    ("seedfisheye:fov=140", (128, 128)),
    ("cubemap", (192, 128)),
    ("cubemap:layout=1x6", (32, 192)),
    ("cubemap:layout=4x3", (256, 192)),
    ("eac", (192, 128)),
    ("eac:pad=2", (192, 128)),
    ("dual-fisheye:fov=200", (256, 128)),
    ("cylindrical", (256, 160)),
    ("cylindrical:fov=180,vfov=120", (192, 128)),
    ("cylindrical-equal-area", (256, 82)),
    ("cylindrical-equal-area:vfov=180", (256, 128)),
    ("mercator", (192, 192)),
    ("mercator:fov=200,vfov=150", (192, 128)),
    ("pannini", (192, 128)),
    ("pannini:d=2,fov=239.9", (256, 128)),  # at its widest: x turns back at 240 degrees
    ("pannini:d=1,fov=200,vcomp=0.5", (256, 128)),
    ("hammer", (256, 128)),
    ("sinusoidal", (256, 128)),
    ("half-equirect", (128, 128)),
    ("little-planet", (128, 128)),
    ("octahedron", (128, 128)),
    ("swirl:amount=3", (128, 128)),
    ("distortion:k1=-0.2,fov=100", (160, 120)),
    ("brown:k1=0.05,fov=90", (160, 120)),
]


def ray_panorama() -> np.ndarray:
    pano = Camera.from_spec("equirect", PANO)
    ys, xs = np.mgrid[0:PANO[1], 0:PANO[0]] + 0.5
    d, _ = pano.lens.pixel_to_dir(np.stack([xs, ys], -1))
    return d.astype(np.float32)


RAYS = ray_panorama()


def angles(colours: np.ndarray, rays: np.ndarray) -> np.ndarray:
    c = colours.astype(np.float64)
    c /= np.linalg.norm(c, axis=-1, keepdims=True)
    return 2 * np.arcsin(np.clip(np.linalg.norm(c - rays, axis=-1) / 2, 0, 1))


def centre_rays(lens) -> tuple[np.ndarray, np.ndarray]:
    ys, xs = np.mgrid[0:lens.height, 0:lens.width] + 0.5
    return lens.pixel_to_dir(np.stack([xs, ys], -1))


@pytest.mark.parametrize("exact", [True, False], ids=["exact-map", "lattice"])
@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_each_output_pixel_gets_its_own_ray(spec, size, exact):
    src, dst = Camera.from_spec("equirect", PANO), Camera.from_spec(spec, size)
    out, alpha = warp(RAYS, src, dst, exact_map=exact)
    rays, ok = centre_rays(dst.lens)
    keep = ok & (alpha > 0.999)
    assert keep.mean() > 0.3
    err = angles(out[keep], rays[keep])
    assert err.max() < TOL, (err.max(), np.argwhere(keep)[np.argmax(err)])
    if spec.startswith("dual-fisheye"):  # the overlap is checked too: rays over 90 degrees off their lens's axis
        back = np.arange(size[0])[None, :].repeat(size[1], 0) >= size[0] / 2
        overlap = keep & np.where(back, rays[..., 2] > 0, rays[..., 2] < 0)
        assert overlap.sum() > 100
    if spec.startswith("eac"):  # and the pixels along every face edge
        lens = dst.lens
        fw = lens.width * (1 - 2 * lens.pu) / 3
        cols = ((np.arange(size[0]) + 0.5 - lens.pad) / fw) % 1
        assert keep[:, (cols < 1 / fw) | (cols > 1 - 1 / fw)].sum() > 4 * size[1] // 2


#: models read back into a panorama: (spec, size); bilinear reads of the model's own pixels, whose
#: angular size is up to ~2 pi / 512: TOL_BACK = (2 pi / 512)^2 / 4, twice the bound of TOL's reasoning
READ_BACK = [
    ("dual-fisheye:fov=200", (1024, 512)),  # the overlap is read from the nearer lens
    ("eac", (768, 512)),
    ("pannini:d=2,fov=239.9", (1024, 512)),
    ("fisheye:dfov=180", (768, 512)),
    ("hammer", (1024, 512)),
    ("mercator", (512, 512)),
    ("little-planet", (512, 512)),
    ("octahedron", (512, 512)),
]
TOL_BACK = (2 * np.pi / 512) ** 2 / 4


@pytest.mark.parametrize("spec,size", READ_BACK, ids=[c[0] for c in READ_BACK])
def test_a_model_image_of_rays_reads_back_as_the_panorama_rays(spec, size):
    src = Camera.from_spec(spec, size)
    image, ok = centre_rays(src.lens)
    dst = Camera.from_spec("equirect", (256, 128))
    out, alpha = warp(image.astype(np.float32), src, dst, exact_map=True)
    rays, _ = centre_rays(dst.lens)
    # leave out samples whose bilinear taps reach a pixel without a ray (outside a circle or an outline),
    # and EAC's face edges (checked below: the ray field has a kink there, and across the boundary
    # between its two rows the faces are neighbours only on the cube, not in the layout)
    from lenslab.warp.maps import exact_map

    ys, xs = np.mgrid[0:128, 0:256] + 0.5
    q, qok = exact_map(src, dst, np.stack([xs, ys], -1))
    keep = qok & (alpha > 0.999)
    for dx in (-1.0, 0.0, 1.0):
        for dy in (-1.0, 0.0, 1.0):
            tap = q + [dx, dy]
            keep &= src.lens.pixel_to_dir(tap)[1] & src.lens.in_image(tap)  # no clamped taps either
    if spec == "eac":
        fx = q[..., 0] / (size[0] / 3)
        fy = q[..., 1] / (size[1] / 2)
        near_edge = qok & (alpha > 0.999) & ((np.abs(fx - np.round(fx)) * size[0] / 3 < 1.0)
                                             | (np.abs(fy - np.round(fy)) * size[1] / 2 < 1.0))
        # taps across a face edge read the face across it on the cube: within a pixel's angle of the ray
        # (reading the next pixel of the layout instead is tens of degrees off across the two rows)
        assert near_edge.sum() > 100
        assert angles(out[near_edge], rays[near_edge]).max() < np.pi / 2 / (size[1] / 2)
        keep &= ~near_edge
    assert keep.sum() > 2000
    err = angles(out[keep], rays[keep])
    # where the model stretches its pixels over wide angles (Pannini at its widest edge, Hammer near its
    # poles and outline) the field bends faster than TOL_BACK assumes: there the bound is the error of a
    # float64 bilinear interpolation of the model's exact rays at the sample (the least any bilinear read
    # can do), plus float32 colours; such places must stay few
    bound = np.maximum(TOL_BACK, 1.001 * bilinear_error(src.lens, q[keep]) + 1e-6)
    assert (err <= bound).all(), (err.max(), np.argwhere(keep)[np.argmax(err - bound)])
    assert (bound > TOL_BACK).mean() < 0.1


def bilinear_error(lens, q: np.ndarray) -> np.ndarray:
    """Angle between the ray at ``q`` and the float64 bilinear interpolation of the rays at the centres
    of the four pixels around it."""
    p = q - 0.5
    i0, j0 = np.floor(p[:, 0]), np.floor(p[:, 1])
    fx, fy = (p[:, 0] - i0)[:, None], (p[:, 1] - j0)[:, None]
    tap = lambda di, dj: lens.pixel_to_dir(np.c_[i0 + di + 0.5, j0 + dj + 0.5])[0]  # noqa: E731
    mix = (tap(0, 0) * (1 - fx) * (1 - fy) + tap(1, 0) * fx * (1 - fy) + tap(0, 1) * (1 - fx) * fy
           + tap(1, 1) * fx * fy)
    return angles(mix, lens.pixel_to_dir(q)[0])
