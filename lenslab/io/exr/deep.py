"""A deep EXR part read as the flat image a compositor makes of it.

OpenEXR's Python bindings decode the part (``OpenEXR.File(path).parts[i].channels[name].pixels``: an object
array with each pixel's samples, None where it has none); the samples are gathered into one array per
channel (no loop per pixel in Python) and flattened by :func:`lenslab.io.exr.flatten.flatten`: sorted front
to back by ``Z``, coinciding samples merged, volume samples (``ZBack``) split where they overlap, and
composited with "over", colour premultiplied by alpha as deep samples and flat EXR images store it.

Each colour channel takes its associated alpha as the OpenEXR document on deep pixels says (``AR``, ``AG``,
``AB`` for R, G, B where present, else ``A``; other channels ``A``); depth comes from the base layer's ``Z``
and ``ZBack``. The flat ``Z`` (an extra channel) is the front of the nearest sample with alpha above 0, +inf
where the pixel has none; ``ZBack`` is not kept. The sample counts were checked against the input budget
before (:mod:`lenslab.io.exr.deep_counts`).
"""

from __future__ import annotations

import itertools
import operator

import numpy as np

from lenslab.errors import FormatError, clip

DEPTH = ("Z", "ZBack")


def _alpha_of(short: str, present: set[str]) -> str | None:
    """The alpha channel (short name) a channel is associated with, or None."""
    own = {"R": "AR", "G": "AG", "B": "AB"}.get(short)
    if own in present:
        return own
    return "A" if "A" in present else None


def _gather(path, chans: dict, wanted: set[str], w: int, h: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(sample count of each pixel, flat, row-major) and {channel name: (N,) samples} of the ``wanted``
    channels, from the bindings' per-pixel arrays (channel groups such as ``RGBA`` split by name)."""
    counts = has = None
    samples: dict[str, np.ndarray] = {}
    for key, ch in chans.items():
        pix = ch.pixels
        if pix is None or pix.dtype != object or pix.shape != (h, w):
            raise FormatError(f"{path}: deep channel {clip(key)} does not match the data window {w} x {h}; the file "
                              "is damaged")
        flat = pix.reshape(-1)
        if has is None:  # the pixels with samples and their counts: one table for every channel, as in the file
            has = np.fromiter(map(operator.is_not, flat, itertools.repeat(None)), bool, flat.size)
        present = flat[has]
        layer, _, letters = key.rpartition(".")
        names = [key]
        if present.size and present[0].ndim == 2:  # a group the bindings interleave (RGB, RGBA): one per letter
            names = [f"{layer}.{c}" if layer else c for c in letters]
            if len(names) != present[0].shape[1]:
                raise FormatError(f"{path}: OpenEXR gave {present[0].shape[1]} channels as {clip(key)}; lenslab "
                                  "cannot tell them apart")
        if not wanted & set(names):
            continue
        if counts is None:
            counts = np.zeros(flat.size, np.int64)
            counts[has] = np.fromiter(map(len, present), np.int64, present.size)
        try:
            data = np.concatenate(list(present)) if present.size else np.zeros((0, len(names)), np.float32)
        except (TypeError, ValueError):  # a pixel without samples in this channel but with some in another
            data = None
        if data is None or len(data) != counts.sum():
            raise FormatError(f"{path}: deep channel {clip(key)} has other sample counts than the part's other "
                              "channels; the file is damaged")
        data = data.reshape(len(data), len(names))
        for i, name in enumerate(names):
            if name in wanted:
                samples[name] = data[:, i]
    if counts is None:
        counts = np.zeros(w * h, np.int64)
    return counts, samples


def read_deep(path, index: int, names: list[str], short: dict[str, str], order: list[str | None],
              window: tuple[int, int, int, int], threads: int, extra: list[str], types: dict[str, str]):
    """Part ``index`` flattened, in its data window: float32 ``H x W x C`` with channel ``order[i]`` (short
    names of ``short``; None: 0) in channel ``i``; the extra planes asked for (``extra``, full names: ``Z``
    is the front depth, other channels flattened with their alpha); each image channel's stored type; and
    what the flattening counted (``samples``, ``max_per_pixel``, NaN depths dropped, alphas clamped).
    ``types``: each channel's stored type (HALF, FLOAT, UINT) as lenslab read the header."""
    from lenslab.io.exr.flatten import flatten
    from lenslab.io.exr.whole import part_channels

    x0, y0, x1, y1 = window
    w, h = x1 - x0 + 1, y1 - y0 + 1
    if "Z" not in names:
        raise FormatError(f"{path}: part {index} is a deep image without a Z channel; its samples have no depth to "
                          "be sorted by (OpenEXR requires Z in a deep image)")
    image_names = [short[c] for c in order if c is not None]
    colour = [n for n in image_names + [e for e in extra if e not in DEPTH] if not _is_alpha(n)]
    alphas = {}
    for n in colour:
        layer, _, base = n.rpartition(".")
        a = _alpha_of(base, {k.rpartition(".")[2] for k in names if k.rpartition(".")[0] == layer}) or \
            _alpha_of(base, {k for k in names if "." not in k})
        if a is None:
            raise FormatError(f"{path}: part {index} is a deep image whose channel {clip(n)} has no alpha (A) to "
                              "composite its samples with; lenslab cannot flatten it")
        alphas[n] = (layer + "." + a) if layer and f"{layer}.{a}" in names else a
    groups: dict[str, list[str]] = {}
    for n in colour:
        groups.setdefault(alphas[n], []).append(n)
    for n in image_names + extra:
        if _is_alpha(n) and n not in groups:
            groups[n] = []
    wanted = set(groups) | {c for cs in groups.values() for c in cs} | {"Z"} | ({"ZBack"} & set(names))
    counts, samples = _gather(path, part_channels(path, index, threads, separate=False), wanted, w, h)
    # (OpenEXR's arrays for every pixel are gone here, before the flattening's own arrays are made)
    pixel = np.repeat(np.arange(w * h, dtype=np.int64), counts)
    z = samples["Z"]
    zback = samples.get("ZBack")
    planes: dict[str, np.ndarray] = {}
    info = {"samples": int(counts.sum()), "max_per_pixel": int(counts.max(initial=0)), "dropped_nan_z": 0,
            "alpha_clamped": 0}
    front = None
    for alpha_name, members in groups.items():
        values = np.stack([samples[m] for m in members], 1) if members else np.zeros((pixel.size, 0))
        a, c, front_g, counted = flatten(pixel, z, zback, samples[alpha_name], values, w * h)
        front = front_g if front is None else np.minimum(front, front_g)
        info["dropped_nan_z"] = counted["dropped_nan_z"]
        info["alpha_clamped"] += counted["alpha_clamped"]
        planes[alpha_name] = a.reshape(h, w).astype(np.float32)
        for j, m in enumerate(members):
            planes[m] = c[:, j].reshape(h, w).astype(np.float32)
    if front is None:
        front = np.full(w * h, np.inf)
    planes["Z"] = front.reshape(h, w).astype(np.float32)
    image = np.zeros((h, w, len(order)), np.float32)
    for i, c in enumerate(order):
        if c is not None:
            image[..., i] = planes[short[c]]
    extra_planes = {n: planes[n] for n in extra if n in planes}
    return image, {n: types.get(n, "HALF") for n in image_names}, extra_planes, info


def _is_alpha(name: str) -> bool:
    return name.rpartition(".")[2] in ("A", "AR", "AG", "AB")
