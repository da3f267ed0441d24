"""An ST-map warp with --antialias says so when its map shrinks the source nowhere, as a lens-to-lens warp does.

The maps are written here by hand in Nuke's STMap convention (``s = x / W``, ``t = 1 - y / H``, x, y in pixel
coordinates with centres at +1/2), each the image of a linear map ``A`` of the output pixel centres: its footprints
stretch some direction by the larger singular value of ``A``, taken from LAPACK (numpy.linalg.svd) in float64 and
set against the threshold the command uses (1.05 source pixels). The identity map's output is also compared with
the filter's model over one source pixel (the bilinear source averaged over a 1x1 box: weights 9/16, 3/32, 1/64),
convolved here in float64.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.warp.minification import NOTE, SHRINK, Looked, shrinks
from tests.warp.test_antialias_softening_note import _blurred as _box_of_one_pixel  # 9/16, 3/32, 1/64 in float64

# powers of two: every map entry (k + 1/2) / W is exact in float32, so the identity map reads texel centres exactly
W, H = 64, 32


def _map(a: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The ST map (float32 h x w x 4) of output pixel centre p read at source position ``a @ (p - c) + C`` (c, C the
    output's and the source's centres); alpha 1 everywhere (positions off the source clamp to its edge)."""
    w, h = size
    y, x = np.mgrid[0:h, 0:w] + 0.5
    px, py = x - w / 2, y - h / 2
    sx = a[0, 0] * px + a[0, 1] * py + W / 2
    sy = a[1, 0] * px + a[1, 1] * py + H / 2
    st = np.zeros((h, w, 4), np.float32)
    st[..., 0], st[..., 1], st[..., 3] = sx / W, 1 - sy / H, 1
    return st


def _stretch(a: np.ndarray) -> float:
    return float(np.linalg.svd(np.asarray(a, np.float64), compute_uv=False)[0])


@pytest.fixture
def plate(tmp_path):
    img = np.random.default_rng(5).random((H, W, 3)).astype(np.float32) * 4
    path = tmp_path / "plate.exr"
    write(path, img, pixel_type="float")
    return path, img


c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
MAPS = {  # name: (linear map of the output into the source, output size)
    "identity": (np.eye(2), (W, H)),
    "rotated 30 degrees": (np.array([[c, -s], [s, c]]), (W, H)),
    "enlarged 1.5x": (np.eye(2) / 1.5, (96, 48)),
    "1.04 across": (np.diag([1.04, 1.0]), (W, H)),
    "1.1 across": (np.diag([1.1, 1.0]), (W, H)),
    "sheared": (np.array([[1.0, 0.5], [0.0, 1.0]]), (W, H)),
    "halved": (np.eye(2) * 2, (W // 2, H // 2)),
}


@pytest.mark.parametrize("name", list(MAPS))
def test_an_st_map_warp_gets_the_note_where_its_footprints_shrink_nothing(plate, tmp_path, capsys, name):
    path, img = plate
    a, size = MAPS[name]
    st = tmp_path / "map.exr"
    write(st, _map(a, size), pixel_type="float", channels=["R", "G", "B", "A"])
    out = tmp_path / "out.exr"
    rc = main(["warp", str(path), "--stmap", str(st), "-o", str(out), "--antialias", "--pixel-type", "float"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert abs(_stretch(a) - SHRINK) > 0.01  # each map clear of the threshold, so float32 maps cannot cross it
    if _stretch(a) <= SHRINK:  # identity 1, rotation 1, enlarged 2/3, 1.04
        assert err.count("note:") == 1 and f"lenslab warp: note: {path}: {NOTE}" in err
    else:  # 1.1 across, the shear 1.28, halved 2
        assert NOTE not in err


def test_the_identity_st_map_with_antialias_is_the_one_pixel_box(plate, tmp_path):
    from lenslab.stmap import warp_with_st_map

    _, img = plate
    looked = Looked()
    got, alpha = warp_with_st_map(img, _map(np.eye(2), (W, H)), antialias=True, looked=looked)
    assert shrinks(looked) is False
    inner = (slice(1, H - 1), slice(1, W - 1))  # off the edges, where the source clamps (the model's roll wraps)
    # the filter integrates in float64 and rounds once to the float32 output: within 2 float32 ulps (1.2e-7 each)
    np.testing.assert_allclose(got[inner], _box_of_one_pixel(img)[inner], rtol=2.4e-7, atol=0)
    looked = Looked()
    warp_with_st_map(img, _map(np.eye(2) * 2, (W // 2, H // 2)), antialias=True, looked=looked)
    assert shrinks(looked) is True


def test_without_antialias_nothing_is_looked_at(plate):
    from lenslab.stmap import warp_with_st_map

    looked = Looked()
    warp_with_st_map(plate[1], _map(np.eye(2), (W, H)), looked=looked)
    assert shrinks(looked) is None


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(pytest.main([__file__, "-q"]))
