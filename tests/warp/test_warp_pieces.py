"""A piecewise source read across its pieces' edges: a cube map whose pixels hold their own ray
direction, warped with every filter, must show at each output pixel that pixel's own ray, also where
the filter's taps leave a face (they read the neighbouring face, the cube folded flat along the edge)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp import warp

N = 24  # face side in pixels

#: docs/conventions.md's cube faces (ffmpeg v360's 3x2 layout rludfb), transcribed: d ~ f(uf, vf)
FACES = {
    (0, 0): lambda u, v: (np.ones_like(u), -v, -u),   # right
    (1, 0): lambda u, v: (-np.ones_like(u), -v, u),   # left
    (2, 0): lambda u, v: (u, np.ones_like(u), v),     # up
    (0, 1): lambda u, v: (u, -np.ones_like(u), -v),   # down
    (1, 1): lambda u, v: (u, -v, np.ones_like(u)),    # front
    (2, 1): lambda u, v: (-u, -v, -np.ones_like(u)),  # back
}


def cube_directions() -> np.ndarray:
    """Unit ray of every pixel centre of a 3x2 cube map of N-pixel faces (float64, from FACES)."""
    img = np.zeros((2 * N, 3 * N, 3))
    c = (np.arange(N) + 0.5) * 2.0 / N - 1.0
    uf, vf = np.meshgrid(c, c, indexing="xy")
    for (col, row), f in FACES.items():
        d = np.stack(f(uf, vf), axis=-1)
        img[row * N:(row + 1) * N, col * N:(col + 1) * N] = d / np.linalg.norm(d, axis=-1, keepdims=True)
    return img


def equirect_rays(w: int, h: int) -> np.ndarray:
    """Rays of a full-sphere equirect's pixel centres: phi = (2x/W - 1) pi, theta = (1 - 2y/H) pi/2."""
    y, x = np.mgrid[0:h, 0:w] + 0.5
    phi, theta = (2 * x / w - 1) * np.pi, (1 - 2 * y / h) * np.pi / 2
    return np.stack([np.cos(theta) * np.sin(phi), np.sin(theta), np.cos(theta) * np.cos(phi)], axis=-1)


@pytest.mark.parametrize("filter", ["bilinear", "bicubic", "lanczos"])
def test_taps_across_a_face_edge_read_the_neighbouring_face(filter):
    src = Camera.from_spec("cubemap", (3 * N, 2 * N))
    dst = Camera.from_spec("equirect", (256, 128))
    out, alpha = warp(cube_directions().astype(np.float32), src, dst, filter=filter)
    assert alpha.min() == 1.0  # the cube sees every direction
    got = out / np.linalg.norm(out, axis=-1, keepdims=True)
    err = np.degrees(np.arccos(np.clip((got * equirect_rays(256, 128)).sum(-1), -1.0, 1.0)))
    # a pixel's ray is interpolated from rays one to three pixels away on the (folded) cube: its error
    # is a fraction of one pixel's angle, the smallest of which (at a face edge, 2/N in uf at uf = 1) is
    # (1/N) rad = 2.39 degrees; 0.45 degrees measured with bilinear. Taps read across the layout instead
    # are tens of degrees off (57 measured before faces knew their neighbours)
    assert err.max() < 0.25 * np.degrees(1.0 / N)


def test_edge_taps_of_the_front_face_read_its_neighbours_edge_pixels():
    from lenslab.warp.seam import border_of, fold_piece

    border = border_of(Camera.from_spec("cubemap", (3 * N, 2 * N)).lens)
    front = border.grid[1, 1]
    # front covers columns N..2N-1 and rows N..2N-1; the left face is grid cell (1, 0), the up face (2, 0)
    assert fold_piece(N - 1, N + 5, front, border.pieces) == (2 * N - 1, 5)  # left face's last column
    assert fold_piece(N + 5, N - 1, front, border.pieces) == (2 * N + 5, N - 1)  # up face's last row
    assert fold_piece(N - 2, N + 5, front, border.pieces) == (2 * N - 2, 5)  # two deep: one further in
    # on the cube, the pixel read is the mirror image of the front face's edge pixel across the plane
    # of their common edge (x = -z for left, y = z for up): the two straddle the edge symmetrically
    dirs = cube_directions()
    for (i, j), (fi, fj), normal in (((N - 1, N + 5), (N, N + 5), (1.0, 0.0, 1.0)),
                                     ((N + 5, N - 1), (N + 5, N), (0.0, 1.0, -1.0))):
        n = np.array(normal) / np.sqrt(2.0)
        mirror = dirs[fj, fi] - 2.0 * np.dot(dirs[fj, fi], n) * n
        ti, tj = fold_piece(i, j, front, border.pieces)
        np.testing.assert_allclose(dirs[tj, ti], mirror, atol=1e-12)  # float64 rounding of unit vectors


@pytest.mark.parametrize("spec, cells, pixel_deg", [
    ("cubemap:layout=4x3", (4, 3), np.degrees(1.0 / N)),  # smallest cube pixel angle, at a face edge
    ("cubemap:layout=6x1", (6, 1), np.degrees(1.0 / N)),
    ("eac", (3, 2), 90.0 / N),  # equi-angular: every pixel spans 90/N degrees
])
def test_other_layouts_read_their_neighbouring_faces(spec, cells, pixel_deg):
    size = (cells[0] * N, cells[1] * N)
    src = Camera.from_spec(spec, size)
    # each pixel labelled with its own ray (the layout's faces and turns are the lens's business here;
    # what is checked is that the warp reads the right pixels, against the equirect formula's rays)
    y, x = np.mgrid[0:size[1], 0:size[0]] + 0.5
    label, _ = src.lens.pixel_to_dir(np.stack([x, y], axis=-1))
    out, alpha = warp(label.astype(np.float32), src, Camera.from_spec("equirect", (256, 128)), filter="lanczos")
    assert alpha.min() == 1.0
    got = out / np.linalg.norm(out, axis=-1, keepdims=True)
    err = np.degrees(np.arccos(np.clip((got * equirect_rays(256, 128)).sum(-1), -1.0, 1.0)))
    # as for the 3x2 cube map: a fraction of one pixel's angle (0.29 and 0.53 degrees measured)
    assert err.max() < 0.25 * pixel_deg
