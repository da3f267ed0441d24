"""A camera: a lens bound to an image size, a pose (rotation camera -> world) and an eye point.

This is the one camera interface that the warp engine and the tracer share: the tracer's primary
rays come from :meth:`Camera.rays`, and the warp's output directions from :meth:`Camera.pixel_to_world`.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import LensError, clip
from lenslab.lenses.core.base import FLOAT, Lens, as_points, normalize
from lenslab.lenses.core.pose import Pose, rotate_rows
from lenslab.lenses.registry import make_lens


def sample_offsets(samples: int, shape: tuple[int, ...], rng: np.random.Generator | None) -> np.ndarray:
    """Stratified sub-pixel offsets in [0, 1)^2, shape ``shape + (samples, 2)``, float64.

    ``samples = k*k`` gives a k x k grid of strata; any other count gives n-rooks (Latin hypercube)
    strata, one per row and column of an n x n grid. With ``rng=None`` the samples sit at the strata
    centres (a fixed grid, noise-free); otherwise each is jittered within its stratum.
    """
    if samples < 1:
        raise LensError(f"samples per pixel must be at least 1, got {samples}")
    k = int(round(np.sqrt(samples)))
    full = shape + (samples,)
    if k * k == samples:
        idx = np.arange(samples)
        sx = np.broadcast_to((idx % k).astype(FLOAT), full)
        sy = np.broadcast_to((idx // k).astype(FLOAT), full)
        n = float(k)
    else:
        n = float(samples)
        sx = np.broadcast_to(np.arange(samples, dtype=FLOAT), full)
        if rng is None:  # a fixed n-rooks pattern: column i -> row (i * p) mod n with p coprime to n
            p = next(q for q in range(max(1, int(np.sqrt(samples))), samples + 1) if np.gcd(q, samples) == 1)
            sy = np.broadcast_to(((np.arange(samples) * p) % samples).astype(FLOAT), full)
        else:
            sy = np.argsort(rng.random(full), axis=-1).astype(FLOAT)
    if rng is None:
        jx = jy = 0.5
    else:
        jx, jy = rng.random(full), rng.random(full)
    return np.stack([(sx + jx) / n, (sy + jy) / n], axis=-1)


class Camera:
    """A lens (with its image size), a pose and an eye point: what a warp reads from and renders into.

    Parameters
    ----------
    lens : lenslab.lenses.Lens
        The lens model with its image size (:func:`lenslab.make_lens`).
    pose : lenslab.lenses.Pose, optional
        Rotation camera -> world and the eye point; default: the identity at the origin (looking along
        world ``+z``, ``+y`` up).

    Examples
    --------
    >>> import lenslab
    >>> cam = lenslab.Camera.from_spec("perspective:fov=90", (640, 480), yaw=90)
    >>> cam.size
    (640, 480)
    >>> origins, dirs, valid = cam.pixel_to_world([[320.0, 240.0]])   # the image centre
    >>> dirs.round(6).tolist()    # yaw 90 turns forward (+z) to the right (+x)
    [[1.0, 0.0, 0.0]]
    """

    def __init__(self, lens: Lens, pose: Pose | None = None) -> None:
        if not isinstance(lens, Lens):
            raise LensError(f"a camera needs a Lens, got {type(lens).__name__}")
        self.lens = lens
        self.pose = pose or Pose()

    @classmethod
    def from_spec(cls, spec: str, size: tuple[int, int], yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0,
                  eye: Sequence[float] = (0.0, 0.0, 0.0), look_at: Sequence[float] | None = None,
                  up: Sequence[float] = (0.0, 1.0, 0.0)) -> "Camera":
        """A camera from a lens spec (or camera file), an image size and a pose.

        Parameters
        ----------
        spec : str
            A lens spec or camera file, as :func:`lenslab.make_lens` takes.
        size : tuple of int
            ``(width, height)`` in pixels.
        yaw, pitch, roll : float
            Degrees: yaw turns right, pitch up, roll counter-clockwise, applied roll, then pitch, then
            yaw (the conventions page gives the matrices).
        eye : sequence of float
            The eye point in world coordinates.
        look_at, up : sequence of float, optional
            Instead of yaw, pitch and roll: the camera looks from ``eye`` at ``look_at``, ``+y`` leaning
            toward ``up``.

        Returns
        -------
        Camera
        """
        lens = make_lens(spec, size)
        pose = Pose.look_at(eye, look_at, up) if look_at is not None else Pose.from_ypr(yaw, pitch, roll, eye)
        return cls(lens, pose)

    @property
    def width(self) -> int:
        return self.lens.width

    @property
    def height(self) -> int:
        return self.lens.height

    @property
    def size(self) -> tuple[int, int]:
        return self.lens.width, self.lens.height

    def pixel_to_world(self, xy: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World ray origins, unit world directions (float64) and validity for pixel coordinates."""
        d, valid = self.lens.pixel_to_dir(xy)
        dw = rotate_rows(d, self.pose.rotation)
        if np.any(self.lens.eye_offsets != 0):  # per-pixel eye points (tiled multi-view)
            origins = rotate_rows(self.lens.pixel_origin(xy), self.pose.rotation)
            origins += self.pose.eye
        else:
            origins = np.empty(d.shape, dtype=FLOAT)
            origins[...] = self.pose.eye
        return origins, dw, valid

    def world_to_pixel(self, dirs: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Pixel coordinates and validity of world directions seen from the eye."""
        d = rotate_rows(as_points(dirs, 3, "directions"), self.pose.rotation.T)  # world -> camera (R^T d)
        return self.lens.dir_to_pixel(d)

    def pixel_grid(self, rows: slice | None = None, samples: int = 1, seed: int | None = None) -> np.ndarray:
        """Continuous pixel coordinates of the sub-pixel samples, shape ``(h, W, samples, 2)``, float64.

        Deterministic per image row for a given seed, so a band renders the same whatever the banding.
        ``seed=None`` puts samples at the strata centres (with one sample: the pixel centres).
        """
        r0, r1, _ = (rows or slice(0, self.height)).indices(self.height)
        ys = np.arange(r0, r1, dtype=FLOAT)
        xs = np.arange(self.width, dtype=FLOAT)
        if seed is None:
            off = sample_offsets(samples, (1, 1), None)
            off = np.broadcast_to(off, (len(ys), self.width, samples, 2))
        else:
            off = np.empty((len(ys), self.width, samples, 2))
            for i, y in enumerate(range(r0, r1)):
                rng = np.random.default_rng((int(seed), y))
                off[i] = sample_offsets(samples, (self.width,), rng)
        grid = np.empty((len(ys), self.width, samples, 2), dtype=FLOAT)
        grid[..., 0] = xs[None, :, None] + off[..., 0]
        grid[..., 1] = ys[:, None, None] + off[..., 1]
        return grid

    def rays(self, samples: int = 1, seed: int | None = 0,
             rows: slice | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Primary rays for stratified sub-pixel samples.

        Returns ``(origins, directions, valid)`` with shapes ``(h, W, samples, 3)``, ``(h, W, samples, 3)``
        and ``(h, W, samples)``; float64 world coordinates, unit directions. ``rows`` selects a band.
        """
        grid = self.pixel_grid(rows, samples, seed)
        return self.pixel_to_world(grid)

    # -- serialisation ---------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        return {"lens": self.lens.to_dict(), **self.pose.to_dict()}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Camera":
        try:
            lens_d = d["lens"]
        except (KeyError, TypeError):
            raise LensError("camera description has no [lens] table") from None
        if not isinstance(lens_d, dict):
            size = d.get("size")
            if not (isinstance(size, (list, tuple)) and len(size) == 2
                    and all(isinstance(v, int) and not isinstance(v, bool) for v in size)):
                raise LensError(f"camera description: size must be [width, height] in pixels, got {clip(size)}")
            if not isinstance(lens_d, str):
                raise LensError(f"camera description: lens must be a spec or a table, got {clip(lens_d)}")
        lens = make_lens(lens_d) if isinstance(lens_d, dict) else make_lens(lens_d, tuple(d["size"]))
        return cls(lens, Pose.from_dict({k: v for k, v in d.items() if k not in ("lens", "size")}))

    def to_toml(self) -> str:
        import tomli_w

        return tomli_w.dumps(self.to_dict())

    @classmethod
    def from_toml(cls, text: str) -> "Camera":
        from lenslab.inputs.safeload import load_toml

        return cls.from_dict(load_toml(text, "camera TOML", LensError))

    def __repr__(self) -> str:
        yaw, pitch, roll = self.pose.ypr  # (of the turn after the mirror of a mirrored view, which is named first)
        mirror = f"mirror={self.pose.mirror!r}, " if self.pose.mirror else ""
        return (f"Camera({self.lens!r}, {mirror}yaw={yaw:g}, pitch={pitch:g}, roll={roll:g}, "
                f"eye={self.pose.eye.tolist()})")


def rotation_between(src: Camera, dst: Camera) -> np.ndarray:
    """Matrix taking ``dst`` camera-space directions into ``src`` camera space: ``R_src^T R_dst``."""
    return src.pose.rotation.T @ dst.pose.rotation


__all__ = ["Camera", "Pose", "sample_offsets", "rotation_between", "normalize"]
