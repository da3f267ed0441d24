"""Multi-view outputs from several sources: one panorama per tile of a camera made of tiles."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import WarpError
from lenslab.io.alpha import settle
from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan
from lenslab.warp.filters import all_finite
from lenslab.warp.tiles import has_camera_pieces, render_region, tile_cameras


def warp_tiles(images: Sequence[ArrayLike | None], src_cameras: Sequence[Camera], dst_camera: Camera,
               alpha_channel: bool | None = None, **options: Any) -> tuple[np.ndarray, np.ndarray]:
    """Warp one source per tile into a camera made of tiles: tile ``k`` from ``images[k]`` seen by ``src_cameras[k]``.

    For multi-view outputs whose tiles stand at different eye points (a light-field grid, a camera
    rig), with one panorama recorded at each tile's eye: :func:`~lenslab.warp.engine.warp` refuses
    such an output from one panorama, since it would need parallax.

    Parameters
    ----------
    images : sequence of array_like or None
        One source image per tile, in the order of :func:`~lenslab.warp.tiles.tile_cameras`; None (or a
        list shorter than the tiles) leaves a tile empty (alpha 0). All have the same channels.
    src_cameras : sequence of Camera
        The camera of each source image.
    dst_camera : Camera
        The output, a camera whose lens is made of tiles (``tiled:...`` with each tile's pose and eye).
    alpha_channel : bool, optional
        Whether the sources' last channel is alpha (as in :func:`~lenslab.warp.engine.warp`).
    **options
        Those of :func:`~lenslab.warp.engine.warp`: ``filter``, ``samples``, ``antialias``, ``progress``...

    Returns
    -------
    image : numpy.ndarray
        float32 ``H x W x C``, colour premultiplied by the coverage.
    alpha : numpy.ndarray
        float32 ``H x W`` coverage, 0 in empty tiles.

    Raises
    ------
    lenslab.errors.WarpError
        An output that is not made of tiles, more images than tiles, a count of images and cameras that
        differ, sources of different channels, or a source with NaN or infinite values.

    Examples
    --------
    Two views 10 cm apart, side by side, each from a flat panorama recorded at its eye: each tile
    shows its own source, all covered:

    >>> import numpy as np
    >>> from lenslab.lenses import Camera, Pose, make_lens
    >>> from lenslab.warp import tile_cameras, warp_tiles
    >>> views = [{"lens": "perspective:fov=90", "yaw": 90.0 * k, "eye": [0.1 * k, 0, 0]} for k in range(2)]
    >>> rig = Camera(make_lens("tiled:2x1", (64, 32), tiles=views))
    >>> panos = [np.full((16, 32, 3), value, np.float32) for value in (1.0, 2.0)]
    >>> from lenslab.lenses.projections.equirect import Equirect
    >>> sources = [Camera(Equirect(32, 16), Pose(np.eye(3), cam.pose.eye)) for _, _, cam in tile_cameras(rig)]
    >>> image, alpha = warp_tiles(panos, sources, rig)
    >>> float(image[16, 16, 0]), float(image[16, 48, 0]), float(alpha.min())
    (1.0, 2.0, 1.0)
    """
    if not has_camera_pieces(dst_camera):
        raise WarpError(f"warp_tiles needs an output camera made of tiles, got {dst_camera.lens.spec()}; use warp() instead")
    tiles = tile_cameras(dst_camera)
    images, src_cameras = list(images), list(src_cameras)
    if len(images) != len(src_cameras) or len(images) > len(tiles):
        raise WarpError(f"give one image and one source camera per tile ({len(tiles)} tiles); got "
                        f"{len(images)} images and {len(src_cameras)} cameras")
    progress = options.pop("progress", None)
    out = alpha = None
    channels = None
    for (x0, y0, cam), img, src in zip(tiles, images, src_cameras):
        if img is None or cam is None:
            continue
        plan = WarpPlan(src, cam, **options)
        arr = plan.check_image(img)
        if channels is None:
            channels = arr.shape[2]
            out = np.zeros((dst_camera.height, dst_camera.width, channels), dtype=np.float32)
            alpha = np.zeros((dst_camera.height, dst_camera.width), dtype=np.float32)
        elif arr.shape[2] != channels:
            raise WarpError(f"every tile's source must have the same channels; got {channels} and {arr.shape[2]}")
        render_region(plan, arr, out, alpha, x0, y0, progress, alpha_channel)
    if out is None:
        raise WarpError("no tile has both a camera and a source image: nothing to warp")
    if not all_finite(out):
        raise WarpError("a tile's source holds NaN or infinite values; clean it first (e.g. lenslab convert "
                        "repairs and reports them)")
    settle(out, alpha, alpha_channel)
    return out, alpha


__all__ = ["warp_tiles"]
