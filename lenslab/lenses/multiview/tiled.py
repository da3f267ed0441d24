"""A tiled multi-view image: a grid of full cameras, each with its own lens, pose and eye point."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import (FLOAT, Lens, Param, Piece, PixelKernel, ReferencePoint, as_points, check_size,
                                     clean, normalize)
from lenslab.lenses.core.pose import Pose, rotate_rows
from lenslab.lenses.registry import make_lens, register


#: pixels by which dir_to_pixel keeps a point off the right and bottom edges of its tile
BORDER_NUDGE = 1e-9


def parse_grid(grid: str) -> tuple[int, int]:
    """``"3x2"`` -> ``(3, 2)`` (columns, rows)."""
    text = str(grid).strip().lower()
    c, sep, r = text.partition("x")
    try:
        cols, rows = int(c), int(r)
    except ValueError:
        cols = rows = 0
    if not sep or cols < 1 or rows < 1:
        raise LensError(f"tiled: grid={grid!r} must be COLSxROWS with positive integers, e.g. 2x2 or 3x1")
    return cols, rows


def read_tiles_file(path: str | Path) -> list[dict[str, Any]]:
    """The ``[[tiles]]`` tables of a TOML file (one per tile, in tile order; ``{}`` for an empty tile)."""
    from lenslab.inputs.safeload import load_toml
    from lenslab.inputs.sidefile import read_side_text

    path = Path(path)
    data = load_toml(read_side_text(path, "tiles file", 4 << 20), path, LensError)
    tiles = data.get("tiles", data.get("tile"))
    if not isinstance(tiles, list):
        raise LensError(
            f"tiled: {path} has no [[tiles]] tables; give one per tile, in tile order, e.g.\n"
            '  [[tiles]]\n  lens = "perspective:fov=60"\n  yaw = 0\n  eye = [0, 0, 0]'
        )
    return tiles


class Tile:
    """One tile: a lens bound to the tile size and a pose relative to the tiled camera."""

    __slots__ = ("lens", "pose", "turn", "cos_reach")

    def __init__(self, lens: Lens, pose: Pose):
        self.lens, self.pose = lens, pose
        # the rotation, or None when it is the identity (then the tile's directions need no turn)
        self.turn = None if np.array_equal(pose.rotation, np.eye(3)) else pose.rotation
        self.cos_reach = reach_cosine(lens)

    def to_dict(self) -> dict[str, Any]:
        return {"lens": self.lens.to_dict(), **self.pose.to_dict()}


#: margin added to the sampled reach of a tile's lens: the largest angle between samples 1/64 of the
#: image apart cannot exceed the sampled largest by more than this for any model of this package
REACH_MARGIN = np.radians(5.0)


def reach_cosine(lens: Lens) -> float:
    """Cosine of an angle from the lens axis (+z) beyond which the lens certainly sees nothing, or -1.

    Sampled over a 65 x 65 grid and the border of the image, plus :data:`REACH_MARGIN`. ``dir_to_pixel``
    of a tiled lens skips a tile's lens for directions outside its reach (a cheap dot product).
    """
    t = np.linspace(0.0, 1.0, 65)
    edge = np.linspace(0.0, 1.0, 1025)
    pts = [np.stack(np.meshgrid(t, t), axis=-1).reshape(-1, 2)]
    for e in (0.0, 1.0):
        pts += [np.c_[edge, np.full_like(edge, e)], np.c_[np.full_like(edge, e), edge]]
    xy = np.concatenate(pts) * (lens.width, lens.height)
    d, ok = lens.pixel_to_dir(xy)
    if not ok.any():
        return -1.0
    reach = float(np.max(np.arccos(np.clip(d[ok, 2], -1.0, 1.0)))) + REACH_MARGIN
    return -1.0 if reach >= np.pi else float(np.cos(reach))


@register
class Tiled(Lens):
    r"""Tiled multi-view: a ``cols x rows`` grid of tiles, each a full camera with its own lens and pose.

    Tile ``k = row * cols + col`` (left to right, then top to bottom) covers the pixels
    ``[col W/cols, (col+1) W/cols) x [row H/rows, (row+1) H/rows)`` (the last column and row include the
    right and bottom edges); a pixel maps through its tile's lens at local coordinates
    ``(x - col W/cols, y - row H/rows)``, then the tile's rotation: ``d = R_tile d_local``. Ray origins
    are the tile's eye (relative to the tiled camera's eye, in its frame): :meth:`pixel_origin`, and
    :attr:`eye_offsets` lists the distinct ones. Pixels of a tile with no camera are invalid.

    The inverse, ``dir_to_pixel``, returns the pixel of the *first* tile (in tile order) whose lens sees
    the direction, and ignores the tiles' eye offsets (it answers for directions, not for points).

    Tiles come from a TOML file (``tiled:2x2,tiles=cams.toml``) with one ``[[tiles]]`` table per tile,
    or a list of tables, each ``lens`` (a spec or a table) plus a pose (``yaw``/``pitch``/``roll`` or
    ``at``/``up`` or ``rotation``) and ``eye``; an empty table is a tile with no camera (a relative
    file name is read from the current folder, or, inside a camera file, next to it). Without tiles,
    every tile is a 90-degree perspective camera turned by ``360 k / n`` degrees of yaw.
    """

    name = "tiled"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('tiled:2x2', (8192, 4096)),
        ('tiled:3x1', (8190, 2000)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('tiled:2x2', (800, 600), (250.5, 100.25),
                       (0.23799235705918526, 0.2344578171028608, 0.9425439883532094),
                       'tile 0 (top left) is a fov-90 pinhole facing forward'),
    )
    summary = "grid of full cameras (lens, pose, eye per tile), e.g. tiled:2x2,tiles=cams.toml"
    positional = "grid"
    params = (
        Param("grid", "2x2", "COLSxROWS; tile index = row*cols + col"),
        Param("tiles", "", "TOML file with one [[tiles]] table per tile (lens, pose, eye); "
              "empty: 90-degree perspective tiles around the horizon"),
    )

    def __init__(self, width: int, height: int, grid: str = "2x2", tiles: Any = "", **unknown: Any):
        self.width, self.height = check_size(width, height)
        if unknown:
            raise LensError(f"tiled: unknown parameter(s) {', '.join(sorted(unknown))}; valid: grid, tiles")
        self.cols, self.rows = parse_grid(grid)
        self.grid = f"{self.cols}x{self.rows}"
        if self.width % self.cols or self.height % self.rows:
            raise LensError(
                f"tiled: the image size {self.width}x{self.height} does not split into {self.grid} whole tiles; "
                f"use a width divisible by {self.cols} and a height divisible by {self.rows}"
            )
        self.tile_size = (self.width // self.cols, self.height // self.rows)
        n = self.cols * self.rows
        self.tiles_path = ""
        if tiles is None or (isinstance(tiles, str) and not tiles.strip()):
            entries: list[Any] = [
                {"lens": "perspective:fov=90", "yaw": 360.0 * k / n} for k in range(n)
            ]
        elif isinstance(tiles, (str, Path)):
            self.tiles_path = str(tiles)
            entries = read_tiles_file(tiles)
        else:
            entries = list(tiles)
        if len(entries) > n:
            raise LensError(f"tiled: {len(entries)} tiles given for a {self.grid} grid of {n}; "
                            f"use a larger grid or fewer tiles")
        self.tile_list: list[Tile | None] = [self._make_tile(k, e) for k, e in enumerate(entries)]
        self.tile_list += [None] * (n - len(self.tile_list))

    def _make_tile(self, k: int, entry: Any) -> Tile | None:
        if entry is None:
            return None
        if isinstance(entry, Tile):
            entry = entry.to_dict()
        elif hasattr(entry, "lens") and hasattr(entry, "pose"):  # a Camera
            return Tile(entry.lens.with_size(*self.tile_size), entry.pose)
        if not isinstance(entry, dict):
            raise LensError(f"tiled: tile {k} must be a table (lens, pose, eye), got {type(entry).__name__}")
        if not entry:
            return None
        if "lens" not in entry:
            raise LensError(f"tiled: tile {k} has no lens; give e.g. lens = \"perspective:fov=60\"")
        lens = make_lens(entry["lens"], self.tile_size)
        pose = Pose.from_dict({key: val for key, val in entry.items() if key not in ("lens", "size")})
        return Tile(lens, pose)

    # -- identity ----------------------------------------------------------------------------
    def param_values(self) -> dict[str, Any]:
        return {"grid": self.grid, "tiles": [t.to_dict() if t is not None else {} for t in self.tile_list]}

    def spec(self) -> str:
        """``tiled:COLSxROWS`` (plus ``tiles=FILE`` when loaded from one); :meth:`to_dict` has every tile."""
        return f"tiled:{self.grid}" + (f",tiles={self.tiles_path}" if self.tiles_path else "")

    # -- geometry ----------------------------------------------------------------------------
    def tile_index(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tile index and the tile's column and row for each pixel position (-1 where not finite)."""
        tw, th = self.tile_size
        ok = np.all(np.isfinite(xy), axis=-1)
        with np.errstate(invalid="ignore"):
            col = np.clip(np.floor(xy[..., 0] / tw), 0, self.cols - 1)
            row = np.clip(np.floor(xy[..., 1] / th), 0, self.rows - 1)
        col = np.where(ok, col, 0).astype(np.intp)
        row = np.where(ok, row, 0).astype(np.intp)
        return np.where(ok, row * self.cols + col, -1), col, row

    def _per_tile(self, xy: np.ndarray):
        """Yield ``(tile, index, local_xy)`` per tile with a camera and pixels in ``xy`` (flattened to
        ``(n, 2)``): the flat indices of its pixels and their coordinates inside the tile."""
        flat = xy.reshape(-1, 2)
        idx, col, row = self.tile_index(flat)
        tw, th = self.tile_size
        for k, tile in enumerate(self.tile_list):
            if tile is None:
                continue
            sel = np.flatnonzero(idx == k)
            if sel.size == 0:
                continue
            local = np.take(flat, sel, axis=0)
            local[:, 0] -= (k % self.cols) * tw
            local[:, 1] -= (k // self.cols) * th
            yield tile, sel, local

    @staticmethod
    def _rotate(d: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """``d @ rotation.T`` (rows turned by ``rotation``), skipped for the identity."""
        return d if rotation is None else rotate_rows(d, rotation)

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        n = int(np.prod(xy.shape[:-1]))
        d = np.zeros((n, 3), dtype=FLOAT)
        valid = np.zeros(n, dtype=bool)
        for tile, sel, local in self._per_tile(xy):
            dk, vk = tile.lens.pixel_to_dir(local)
            d[sel] = self._rotate(dk, tile.turn)
            valid[sel] = vk
        d = d.reshape(xy.shape[:-1] + (3,))
        valid = valid.reshape(xy.shape[:-1]) & self.in_image(xy)
        return clean(d, valid, inplace=True)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` of the grid when every tile's lens has one the grid's kernel can call
        (``tiled_pixels``: the steps of the NumPy :meth:`dir_to_pixel`, block by block); None otherwise."""
        from lenslab.lenses.core.native import lens_kernels

        k = lens_kernels()
        tw, th = self.tile_size
        records = []
        for j, tile in enumerate(self.tile_list):
            if tile is None:
                continue
            kern = tile.lens.pixel_kernel()
            code = None if kern is None else k.pixel_kernel_ids.get(getattr(kern.fn, "__name__", ""))
            if code is None:
                return None
            turn = np.eye(3) if tile.turn is None else tile.turn
            records.append(np.concatenate([
                [code, kern.params.size, tile.cos_reach], tile.pose.rotation[:, 2], np.asarray(turn).ravel(),
                [(j % self.cols) * tw, (j // self.cols) * th, tw - BORDER_NUDGE, th - BORDER_NUDGE], kern.params]))
        return PixelKernel(k.tiled_pixels, np.concatenate([[len(records)]] + records).astype(FLOAT))

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import dir_to_pixel_through

        return dir_to_pixel_through(self, dirs, self._dir_to_pixel)

    def _dir_to_pixel(self, dirs):
        """The NumPy steps of :meth:`dir_to_pixel` (float64 directions of any length), tile by tile."""
        d = normalize(dirs)
        flat = d.reshape(-1, 3)
        xy = np.zeros((flat.shape[0], 2), dtype=FLOAT)
        # zero vectors (and so non-finite input) are never seen; three column tests beat np.any's reduction
        seen_any = (flat[:, 0] != 0) | (flat[:, 1] != 0) | (flat[:, 2] != 0)
        free = seen_any.copy()  # directions no tile has claimed yet
        tw, th = self.tile_size
        tiles = [(k, t) for k, t in enumerate(self.tile_list) if t is not None]
        # each tile's lens only sees directions within its reach of the tile's axis: one product
        # gives every direction's cosine to every tile axis
        axes = np.array([t.pose.rotation[:, 2] for _, t in tiles]).reshape(-1, 3)
        along = axes @ flat.T  # (tiles, n): one row per tile
        for j, (k, tile) in enumerate(tiles):
            cand = free & (along[j] >= tile.cos_reach) if tile.cos_reach > -1.0 else free
            cand = np.flatnonzero(cand)
            if cand.size == 0:
                continue
            rows = np.take(flat, cand, axis=0)
            if tile.turn is not None:
                rows = rotate_rows(rows, tile.turn.T)  # R^T d, row by row
            local_xy, vk = tile.lens.dir_to_pixel_unit(rows)
            hit = cand[vk]
            # keep points off the tile's right and bottom edges (those pixels belong to the next tile)
            loc = np.minimum(local_xy[vk], (tw - BORDER_NUDGE, th - BORDER_NUDGE))
            loc += ((k % self.cols) * tw, (k // self.cols) * th)
            xy[hit] = loc
            free[hit] = False
        valid = seen_any & ~free
        return xy.reshape(d.shape[:-1] + (2,)), valid.reshape(d.shape[:-1])

    def pieces(self):
        """One piece per tile, each a camera of its own: the tile's lens and pose (None for an empty tile)."""
        tw, th = self.tile_size
        return tuple(Piece(float((k % self.cols) * tw), float((k // self.cols) * th), float(tw), float(th),
                           lens=None if t is None else t.lens, pose=None if t is None else t.pose)
                     for k, t in enumerate(self.tile_list))

    @staticmethod
    def probe_size(values: dict) -> tuple[int, int]:
        """A size the grid of the spec ``values`` splits into whole tiles (to make it and ask its :meth:`default_frame`)."""
        cols, rows = parse_grid(values.get("grid", "2x2"))
        return 256 * cols, 256 * rows

    def default_frame(self, rows: int) -> tuple[int, int]:
        """The size made without ``--size`` from a source of ``rows`` rows over 180 degrees: square tiles of whole
        pixels, each the first camera's field at that resolution (a 90-degree perspective tile ``rows // 2``
        pixels, as a cube face; a 190-degree fisheye ``rows * 190 // 180``), in this grid."""
        lens = next((t.lens for t in self.tile_list if t is not None), None)
        field = 90.0 if lens is None else lens.height / lens.pixels_per_degree()  # degrees down its middle column
        tile = max(1, int(rows * field / 180.0 + 1e-9))
        return self.cols * tile, self.rows * tile

    def pixels_per_degree(self) -> float:
        """The first tile with a camera's: its lens's rows over its field (a 90-degree perspective tile of 256 rows:
        256 / 90), whatever the grid; the rows over 180 degrees for a grid with no camera."""
        lens = next((t.lens for t in self.tile_list if t is not None), None)
        return self.height / 180.0 if lens is None else lens.pixels_per_degree()

    def pixel_origin(self, xy) -> np.ndarray:
        """Each pixel's eye point: its tile's eye (plus the tile lens's own offsets), tiled-camera frame."""
        xy = as_points(xy, 2, "pixel coordinates")
        out = np.zeros((int(np.prod(xy.shape[:-1])), 3), dtype=FLOAT)
        for tile, sel, local in self._per_tile(xy):
            out[sel] = self._rotate(tile.lens.pixel_origin(local), tile.turn) + tile.pose.eye
        return out.reshape(xy.shape[:-1] + (3,))

    @property
    def eye_offsets(self) -> np.ndarray:
        eyes = [rotate_rows(t.lens.eye_offsets, t.pose.rotation) + t.pose.eye for t in self.tile_list if t is not None]
        if not eyes:
            return np.zeros((1, 3), dtype=FLOAT)
        return np.unique(np.concatenate(eyes, axis=0), axis=0)
