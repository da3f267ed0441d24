"""The gain map applied to the base image: the HDR rendition at full headroom (weight 1).

Ultra HDR v1, "Decode" ("Gain map sampling", "Apply the gain map") and Adobe's gain map specification,
"Applying the Gain Map": with ``r`` the gain map sample scaled to 0..1 (code / 255) at a base pixel,

    log_boost = GainMapMin * (1 - r^(1/Gamma)) + GainMapMax * r^(1/Gamma)          (log2, per channel)
    HDR = (SDR + OffsetSDR) * 2^(log_boost * weight) - OffsetHDR

with ``SDR`` the base's linear light (SDR white = 1.0) and ``weight`` = 1, the rendition for a display of
``HDRCapacityMax`` stops of headroom or more. A gain map smaller than the base is sampled bilinearly at the
base's pixel centres, the two images covering the same extent: base pixel ``x`` (centre ``x + 0.5``) is at
``(x + 0.5) * w / W - 0.5`` in gain-map pixels (``w``, ``W`` the two widths; rows the same way), clamped to
the outermost gain-map pixel centres (docs/conventions.md, pixel centres at ``+ 0.5``).

The work goes in bands of :data:`BAND` rows, in float32 (a boost of 2^64, :data:`lenslab.io.gainmap.metadata.MAX_STOPS`,
stays far within float32's range; its relative rounding, 6e-8 a step, is 2^-24 of a value): beside the image,
only the gain map (float32, its own size) and one band's samples are held.
"""

from __future__ import annotations

import numpy as np

from lenslab.io.gainmap.metadata import GainMapMetadata

#: base rows worked at once
BAND = 128


def _taps(n_out: int, n_in: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Left taps, right taps and right weights (float32) of ``n_out`` pixel centres sampled from ``n_in``."""
    u = (np.arange(n_out, dtype=np.float64) + 0.5) * (n_in / n_out) - 0.5
    u = np.clip(u, 0.0, n_in - 1.0)
    left = np.minimum(np.floor(u).astype(np.intp), max(n_in - 2, 0))
    right = np.minimum(left + 1, n_in - 1)
    return left, right, (u - left).astype(np.float32)


def per_channel(codes: np.ndarray, meta: GainMapMetadata) -> bool:
    """Whether the gain differs by colour channel (an RGB map, or metadata per channel): then it applies in the
    base's own primaries, not in Rec.709's."""
    return codes.shape[2] == 3 or any(len(set(v)) > 1 for v in (meta.gain_map_min, meta.gain_map_max, meta.gamma,
                                                                 meta.offset_sdr, meta.offset_hdr))


def application_matrix(gain, profile: bytes | None, channels: int, where: str) -> np.ndarray | None:
    """The 3 x 3 matrix from the linear RGB the gain of ``gain`` (a :class:`lenslab.io.gainmap.GainMap`) applies
    in to Rec.709, or None for Rec.709 itself or where the space does not matter (a gain common to the channels).
    That space is the alternate image's where ISO 21496-1 metadata says so and the gain map image's ICC profile
    names it (``gain.space``), else the base's: its ICC ``profile``'s, sRGB's primaries without one."""
    if channels != 3 or not per_channel(gain.codes, gain.meta):
        return None
    if gain.space is not None:
        return gain.space[1]
    if profile is None:
        return None
    from lenslab.io.colour.icc import plan

    how = plan(profile, channels, where)
    return how.matrix if how.kind == "matrix" else None


def apply_gain(image: np.ndarray, codes: np.ndarray, meta: GainMapMetadata, maxval: int = 255,
               to_rec709: np.ndarray | None = None) -> np.ndarray:
    """Make ``image`` (float32 ``H x W x C``, C 1 or 3, linear, SDR white 1.0) its HDR rendition in place.

    ``codes``: the gain map's samples (``h x w x c``, c 1 or 3, unsigned integers up to ``maxval``), ``h <= H``
    and ``w <= W``. A one-channel base takes a one-channel map with the same metadata for every channel.
    ``to_rec709``: the 3 x 3 matrix that took the base's own linear RGB to ``image``'s Rec.709 (its ICC
    profile's); a gain that differs by channel (:func:`per_channel`) is applied to the base's own RGB, as the
    specifications define it. A gain common to the channels commutes with a matrix that keeps white
    (``M (1, 1, 1) = (1, 1, 1)``: relative colorimetric) and is applied to Rec.709 directly."""
    back = None
    if to_rec709 is not None and image.shape[2] == 3 and per_channel(codes, meta):
        to_rec709 = np.asarray(to_rec709, np.float64)
        back = (np.linalg.inv(to_rec709).astype(np.float32), to_rec709.astype(np.float32))  # (cv2.transform: M x)
    import cv2

    height, width, channels = image.shape
    gain = codes.astype(np.float32) * np.float32(1.0 / maxval)
    if gain.ndim == 2:
        gain = gain[..., None]
    n = channels if per_channel(codes, meta) else 1  # a gain common to the channels is worked out once

    def values(v, dtype=np.float32):
        return np.asarray(v, dtype)[:n]

    lo, inverse_gamma = values(meta.gain_map_min), 1.0 / values(meta.gamma, np.float64)
    span = values(meta.gain_map_max) - lo
    off_sdr, off_hdr = values(meta.offset_sdr), values(meta.offset_hdr)
    y0, y1, ty = _taps(height, gain.shape[0])
    for top in range(0, height, BAND):
        rows = slice(top, min(top + BAND, height))
        s = ty[rows, None, None]
        band = gain[y0[rows]] * (1 - s) + gain[y1[rows]] * s  # (rows, w, c): the rows at the base's centres
        # along each row, OpenCV's bilinear resize samples at (x + 0.5) * w / W - 0.5, edges clamped: the same
        # pixel centres (the rows' scale is 1: each row kept as it is)
        r = cv2.resize(band, (width, band.shape[0]), interpolation=cv2.INTER_LINEAR).reshape(band.shape[0], width, -1)
        if not np.all(inverse_gamma == 1.0):
            r = r ** inverse_gamma.astype(np.float32)
        boost = np.multiply(r, span)  # (a grey map with metadata per channel broadcasts to three channels)
        boost += lo
        np.exp2(boost, out=boost)
        out = image[rows] if back is None else cv2.transform(image[rows], back[0])
        if off_sdr.any():
            out += off_sdr
        out *= boost
        if off_hdr.any():
            out -= off_hdr
        if back is not None:
            image[rows] = cv2.transform(out, back[1])
    return image
