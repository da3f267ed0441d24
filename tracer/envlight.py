"""Environment light: a constant colour, or an HDR equirectangular panorama sampled by importance.

The panorama's pixel <-> direction maps are lenslab's own :class:`~lenslab.lenses.projections.equirect.Equirect`
lens (through a :class:`~lenslab.lenses.core.camera.Camera` carrying the environment's rotation), so the
tracer and the warp engine read a panorama the same way. Radiance is piecewise constant per pixel.

Importance sampling draws a pixel from a 2-D piecewise-constant distribution (a marginal over rows, a
conditional over columns) with weights ``mean(rgb) * cos(latitude)``, then a uniform point inside it.
A pixel covers the solid angle ``cos(lat) dlon dlat`` with ``dlon = 2 pi / W`` and ``dlat = pi / H``
per unit of pixel area, so the solid-angle density of a direction is
``p = pmf(pixel) * W * H / (2 pi^2 cos(lat))``.
"""

from __future__ import annotations

import numpy as np

from tracer.sampling import F32, Distribution1D, uniform_sphere


class ConstantEnvironment:
    """The same radiance from every direction; sampled uniformly over the sphere."""

    def __init__(self, radiance):
        self.radiance = np.asarray(np.broadcast_to(np.asarray(radiance, dtype=F32), (3,)), dtype=F32)
        if not np.all(np.isfinite(self.radiance)) or np.any(self.radiance < 0):
            raise ValueError(f"environment radiance must be finite and non-negative, got {radiance!r}")

    def eval(self, dirs: np.ndarray) -> np.ndarray:
        return np.broadcast_to(self.radiance, (len(dirs), 3)).copy()

    def sample(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Directions and their solid-angle densities for ``(N, 2)`` uniform numbers."""
        d = uniform_sphere(u[:, 0], u[:, 1])
        return d, np.full(len(d), 1.0 / (4 * np.pi), dtype=F32)

    def pdf(self, dirs: np.ndarray) -> np.ndarray:
        return np.full(len(dirs), 1.0 / (4 * np.pi), dtype=F32)

    def describe(self) -> dict:
        return {"radiance": self.radiance.tolist()}


class EquirectEnvironment:
    """An HDR latitude/longitude panorama around the scene (at infinity), optionally rotated.

    ``image`` is ``H x W x 3`` linear float; ``yaw``/``pitch``/``roll`` (degrees) turn the panorama as
    a camera pose would; ``scale`` multiplies the radiance.
    """

    def __init__(self, image: np.ndarray, yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0,
                 scale: float = 1.0, source: str | None = None):
        from lenslab.lenses import Camera

        img = np.asarray(image, dtype=F32)
        if img.ndim == 2:
            img = img[..., None]
        if img.ndim != 3 or img.shape[2] not in (1, 3, 4):
            raise ValueError(f"an environment image must be H x W x 1/3/4, got shape {img.shape}")
        img = img[..., :3] if img.shape[2] >= 3 else np.repeat(img, 3, axis=2)
        img = np.where(np.isfinite(img), np.maximum(img, 0), 0).astype(F32) * F32(scale)
        self.image = np.ascontiguousarray(img)
        self.source = source
        self.height, self.width = img.shape[:2]
        self.camera = Camera.from_spec("equirect", (self.width, self.height), yaw=yaw, pitch=pitch, roll=roll)
        # sampling weights: mean radiance times cos(latitude) at the row centres (the sin(theta) Jacobian)
        rows = np.arange(self.height) + 0.5
        centre = self.camera.lens.pixel_to_dir(np.stack([np.zeros_like(rows) + 0.5, rows], axis=-1))[0]
        cos_lat = np.hypot(centre[:, 0], centre[:, 2])
        w = self.image.mean(axis=2).astype(np.float64) * cos_lat[:, None]
        self.rows = Distribution1D(w.sum(axis=1))
        sums = w.sum(axis=1, keepdims=True)
        # conditional column distribution of each row (uniform in a row that is black throughout)
        self._col_pmf = np.where(sums > 0, w / np.where(sums > 0, sums, 1), 1.0 / self.width)
        cdf = np.concatenate([np.zeros((self.height, 1)), np.cumsum(self._col_pmf, axis=1)], axis=1)
        cdf[:, -1] = 1.0
        # every row's CDF shifted by its row index, so one searchsorted finds the column in any row
        self._col_cdf = (cdf + np.arange(self.height)[:, None]).ravel()
        self.pmf = self.rows.pmf[:, None] * self._col_pmf  # probability of each pixel
        self._flat_rgb = self.image.reshape(-1, 3)

    @classmethod
    def from_file(cls, path, **kwargs) -> "EquirectEnvironment":
        from tracer.imageio import read_image

        image = read_image(path)
        return cls(image, source=str(path), **kwargs)

    def _pixel_index(self, xy: np.ndarray) -> np.ndarray:
        x = np.clip(np.floor(xy[:, 0]).astype(np.int64), 0, self.width - 1)
        y = np.clip(np.floor(xy[:, 1]).astype(np.int64), 0, self.height - 1)
        return y * self.width + x

    def eval(self, dirs: np.ndarray) -> np.ndarray:
        xy, _ = self.camera.world_to_pixel(dirs)
        return self._flat_rgb[self._pixel_index(xy)]

    def _density(self, flat: np.ndarray, cam_dirs: np.ndarray) -> np.ndarray:
        cos_lat = np.hypot(cam_dirs[:, 0], cam_dirs[:, 2])
        jac = (2 * np.pi * np.pi / (self.width * self.height)) * cos_lat
        p = self.pmf.ravel()[flat]
        return np.where(jac > 0, p / np.where(jac > 0, jac, 1), 0).astype(F32)

    def sample(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World directions and solid-angle densities for ``(N, 2)`` uniform numbers."""
        y, row = self.rows.sample_continuous(u[:, 1])
        pos = np.searchsorted(self._col_cdf, row + u[:, 0], side="right") - 1
        col = np.clip(pos - row * (self.width + 1), 0, self.width - 1)
        lo = self._col_cdf[row * (self.width + 1) + col] - row
        width = self._col_pmf[row, col]
        frac = np.clip(np.where(width > 0, (u[:, 0] - lo) / np.where(width > 0, width, 1), 0.5), 0, 1 - 1e-7)
        xy = np.stack([col + frac, y], axis=-1)
        cam_dirs, _ = self.camera.lens.pixel_to_dir(xy)
        dirs = cam_dirs @ self.camera.pose.rotation.T
        return dirs.astype(F32), self._density(row * self.width + col, cam_dirs)

    def pdf(self, dirs: np.ndarray) -> np.ndarray:
        cam_dirs = np.asarray(dirs, dtype=np.float64) @ self.camera.pose.rotation
        xy, _ = self.camera.lens.dir_to_pixel(cam_dirs)
        return self._density(self._pixel_index(xy), cam_dirs / np.linalg.norm(cam_dirs, axis=1, keepdims=True))

    def describe(self) -> dict:
        return {"image": self.source or f"{self.width}x{self.height} array"}
