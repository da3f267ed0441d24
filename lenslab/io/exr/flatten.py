"""Flatten deep samples into one flat pixel each, as OpenEXR's "Interpreting OpenEXR Deep Pixels" defines it.

Arrays in, arrays out (float64), vectorised over every sample of the image: no loop per pixel. Given each
sample's pixel index, front depth ``Z``, back depth ``ZBack`` (or none), alpha and the values of the channels
that alpha is associated with (colour premultiplied by it, as deep samples are stored):

1. Each pixel is made tidy (the document's "Making an Image Tidy"):

   - point samples (``ZBack <= Z``, or no ZBack channel) at the same depth of a pixel merge into one with the
     document's "Merging Overlapping Samples" formula: ``alpha = 1 - prod(1 - a_k)``, colour
     ``alpha / sum(u_k) * sum(c_k v_k)`` with ``u = -log(1 - a)``, ``v = u / a`` (1 where ``a = 0``); where
     opaque samples (``a = 1``) are among them, the mean of the opaque samples' colours (the document's rule
     for two samples, ``(c_i + c_j) / 2`` or the opaque one's colour, taken for any number). The merge is
     associative for samples below alpha 1, so merging them pairwise in any order gives the same sample.
   - volume samples (``Z < ZBack``, both finite) are split at every depth where another sample of the pixel
     starts or ends, and the pieces that then coincide merge with the same formula. A piece of fraction
     ``r`` of a sample has ``u' = r u`` and ``c' v' = r c v``, so the merged piece over ``[b, b')`` is
     ``alpha = 1 - exp(-(b' - b) D)``, ``colour = alpha / ((b' - b) D) * (b' - b) E``, with ``D`` and ``E``
     the sums of ``u / (ZBack - Z)`` and ``c v / (ZBack - Z)`` of the volume samples covering it: a sweep over
     each pixel's sorted boundaries (a segmented scan), never a pair of samples at a time. Opaque volume
     samples make the pieces they cover opaque, of their (mean) colour.
   - a point sample at the front of a volume piece comes before it, one at its back after it (volumes cover
     the half-open interval ``Z <= z < ZBack``).

2. The layers are composited front to back with "over" (``alpha = af + (1 - af) ab``,
   ``c = cf + (1 - af) cb``): ``c = sum_i c_i prod_{j<i}(1 - a_j)``, by a segmented cumulative product.
   Layers behind an opaque one are hidden, never multiplied by 0: a NaN or infinity there does not reach
   the pixel.

Values: alpha is clamped to [0, 1] (the document requires it; the count clamped is returned); a NaN alpha
or colour of a visible layer makes the pixel NaN (NaN alpha: from that layer back); an infinite colour stays
infinite; a sample with a NaN ``Z`` has no place in depth and is dropped (counted); ``Z = inf`` sorts last.
"""

from __future__ import annotations

import numpy as np


def _by_size(counts: np.ndarray):
    """For segments of ``counts`` elements (laid out one after another), grouped by size class (at most a
    power of two): (elements, their row and column in a padded block, the block's shape) per class."""
    counts = np.asarray(counts, np.int64)
    seg = np.repeat(np.arange(counts.size), counts)
    rank = np.arange(seg.size) - (np.cumsum(counts) - counts)[seg]
    level = np.frexp(np.maximum(counts - 1, 0).astype(np.float64))[1]  # 2**level >= count
    elem_level = level[seg]
    for lv in np.unique(elem_level):
        segs = np.flatnonzero((level == lv) & (counts > 0))
        row = np.empty(counts.size, np.int64)
        row[segs] = np.arange(segs.size)
        elems = np.flatnonzero(elem_level == lv)
        yield elems, row[seg[elems]], rank[elems], (segs.size, 1 << int(lv))


def segment_scan(op: np.ufunc, values: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Inclusive scan of ``op`` (``np.add``, ``np.multiply``) within each segment of ``values`` (sorted by
    segment; ``counts[s]`` elements in segment ``s``; extra axes scanned independently), exact per segment
    (no running value carried from one segment into the next). Segments are grouped by size class (powers of
    two) and padded with ``op``'s identity: memory at most twice ``values``'."""
    out = np.empty_like(values)
    for elems, r, c, shape in _by_size(counts):
        if shape[1] == 1:  # segments of one element: the scan is the element
            out[elems] = values[elems]
            continue
        pad = np.full(shape + values.shape[1:], op.identity, values.dtype)
        pad[r, c] = values[elems]
        op.accumulate(pad, axis=1, out=pad)
        out[elems] = pad[r, c]
    return out


def segment_argsort(keys: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The order that sorts ``keys`` (no NaN) within each segment, stably, segments kept in place: the
    order ``np.lexsort((keys, segment))`` gives for segments laid out one after another, by size class."""
    order = np.arange(keys.size)
    for elems, r, c, shape in _by_size(counts):
        if shape[1] == 1:
            continue
        pad = np.full(shape, np.inf)
        pad[r, c] = keys[elems]
        at = np.argsort(pad, axis=1, kind="stable")  # (the padding, +inf, after every key, +inf included)
        start = np.empty(shape[0], np.int64)
        start[r[c == 0]] = elems[c == 0]
        order[elems] = start[r] + at[r, c]
    return order


def _merge_groups(ids: np.ndarray, ngroups: int, a: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One (alpha, colour) per group of coinciding samples (``ids``: each sample's group, sorted), by the
    document's merge formula; a group of one sample keeps it exactly."""
    sizes = np.bincount(ids, minlength=ngroups)
    starts = np.cumsum(sizes) - sizes
    alpha = a[starts].copy()
    colour = c[starts].copy()
    many = sizes > 1
    if not many.any():
        return alpha, colour
    sel = many[ids]
    gi = ids[sel]
    am, cm = a[sel], c[sel]
    opaque = am == 1
    clear = ~opaque & (am < 1)  # (NaN alphas are neither: they make the group NaN below)
    u = np.where(clear, -np.log1p(-np.where(clear, am, 0)), 0.0)
    v = np.where(clear & (am > 0), u / np.where(am > 0, am, 1), 1.0)
    nop = np.bincount(gi, opaque, minlength=ngroups)
    usum = np.bincount(gi, u, minlength=ngroups)
    k = c.shape[1]
    osum = np.stack([np.bincount(gi, np.where(opaque, cm[:, j], 0), minlength=ngroups) for j in range(k)], 1)
    vsum = np.stack([np.bincount(gi, np.where(opaque, 0, cm[:, j] * v), minlength=ngroups) for j in range(k)], 1)
    unknown = np.bincount(gi, np.isnan(am), minlength=ngroups) > 0
    # 1 - prod(1 - a) as -expm1(-sum u): not 1 - (1 - a) rounded to 0 for tiny alphas (the document's
    # example code avoids that rounding for two samples with a1 + a2 - a1 a2)
    ga = np.where(unknown, np.nan, np.where(nop > 0, 1.0, -np.expm1(-usum)))
    w = np.where(usum > 0, ga / np.where(usum > 0, usum, 1), 1.0)
    gc = np.where((nop > 0)[:, None], osum / np.maximum(nop, 1)[:, None], vsum * w[:, None])
    gc = np.where(unknown[:, None], np.nan, gc)
    alpha[many], colour[many] = ga[many], gc[many]
    return alpha, colour


def _volume_layers(pix, z, zb, a, c):
    """Pieces of the volume samples between consecutive boundaries of their pixel (each sample's front and
    back, and the depths of ``extra`` point samples given in ``z == zb`` rows): (pixel, front depth, alpha,
    colour) of each covered piece."""
    vol = zb > z
    length = np.where(vol, zb - z, 1)
    opaque = vol & (a == 1)
    clear = vol & ~opaque
    ac = np.where(clear & (a < 1), a, 0)
    u = -np.log1p(-ac)
    v = np.where(ac > 0, u / np.where(ac > 0, ac, 1), 1.0)
    unknown = clear & np.isnan(a)  # a NaN alpha: NaN from this sample's front back
    d = np.where(unknown, np.nan, np.where(clear, u / length, 0))
    e = np.where(unknown[:, None], np.nan, np.where(clear[:, None], c * (v / length)[:, None], 0))
    oc = np.where(opaque[:, None], c, 0)
    # events: +at the front and -at the back of each volume sample; point depths (z == zb) split with 0
    sign = np.where(vol, 1, 0)
    epix = np.concatenate([pix, pix[vol]])
    edepth = np.concatenate([z, zb[vol]])
    cover = np.concatenate([sign, -sign[vol]]).astype(np.int64)
    nop = np.concatenate([opaque, -opaque[vol].astype(np.int64)]).astype(np.int64)
    dv = np.concatenate([d, -d[vol]])
    ev = np.concatenate([e, -e[vol]])
    ov = np.concatenate([oc, -oc[vol]])
    order = np.lexsort((edepth, epix))
    epix, edepth = epix[order], edepth[order]
    counts = np.bincount(epix, minlength=int(epix.max()) + 1 if epix.size else 0)
    data = np.column_stack([cover[order], nop[order], dv[order], ev[order], ov[order]]).astype(np.float64)
    state = segment_scan(np.add, data, counts)
    last = np.ones(epix.size, bool)  # the last event at each (pixel, depth): the state on [depth, next)
    last[:-1] = (epix[1:] != epix[:-1]) | (edepth[1:] != edepth[:-1])
    idx = np.flatnonzero(last)
    nxt = np.append(idx[1:], -1)
    has_next = (nxt >= 0) & (epix[np.maximum(nxt, 0)] == epix[idx])
    idx, nxt = idx[has_next], nxt[has_next]
    k = c.shape[1]
    st = state[idx]
    covered = np.rint(st[:, 0]) > 0
    idx, nxt, st = idx[covered], nxt[covered], st[covered]
    length = edepth[nxt] - edepth[idx]
    nop_i = np.rint(st[:, 1])
    big_u = np.maximum(st[:, 2], 0) * length
    alpha = np.where(nop_i > 0, 1.0, -np.expm1(-big_u))
    emit = st[:, 3:3 + k] * length[:, None]
    w = np.where(big_u > 0, alpha / np.where(big_u > 0, big_u, 1), 1.0)
    colour = np.where((nop_i > 0)[:, None], st[:, 3 + k:] / np.maximum(nop_i, 1)[:, None], emit * w[:, None])
    return epix[idx], edepth[idx], alpha, colour


def flatten(pixel: np.ndarray, z: np.ndarray, zback: np.ndarray | None, alpha: np.ndarray,
            values: np.ndarray, npix: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """Flatten deep samples (see the module docstring).

    ``pixel`` (N,) int: each sample's pixel in ``range(npix)``; ``z``, ``zback`` (N,) depths (``zback`` None:
    every sample is a point); ``alpha`` (N,); ``values`` (N, K): the channels associated with that alpha.
    Returns float64 ``alpha`` (npix,), ``values`` (npix, K), ``front`` (npix,): the front depth of the
    nearest layer with alpha > 0 (+inf where none), and counts ``{"dropped_nan_z", "alpha_clamped"}``.

    >>> a, c, front, _ = flatten([0, 0], [2.0, 1.0], None, [0.5, 0.5], [[1.0], [2.0]], 2)
    >>> a.tolist(), c[:, 0].tolist(), front.tolist()  # 2 over 1: 2 + (1 - 0.5) * 1; the empty pixel 0
    ([0.75, 0.0], [2.5, 0.0], [1.0, inf])
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # NaN and inf are handled as said
        return _flatten(pixel, z, zback, alpha, values, npix)


def _flatten(pixel, z, zback, alpha, values, npix):
    pixel = np.asarray(pixel, np.int64)
    z = np.asarray(z, np.float64)
    zb = z if zback is None else np.asarray(zback, np.float64)
    a = np.asarray(alpha, np.float64)
    c = np.asarray(values, np.float64)
    c = c.reshape(len(a), c.shape[1] if c.ndim == 2 else 1)
    keep = ~np.isnan(z)
    info = {"dropped_nan_z": int(np.count_nonzero(~keep))}
    if not keep.all():
        pixel, z, zb, a, c = pixel[keep], z[keep], zb[keep], a[keep], c[keep]
    clamped = (a < 0) | (a > 1)
    info["alpha_clamped"] = int(np.count_nonzero(clamped))
    if info["alpha_clamped"]:
        a = np.clip(a, 0, 1)
    vol = (zb > z) & np.isfinite(z) & np.isfinite(zb)
    pts = ~vol
    # point samples: sorted by pixel then depth; those at the same depth of a pixel merge
    p_pix, p_z, p_a, p_c = (pixel, z, a, c) if pts.all() else (pixel[pts], z[pts], a[pts], c[pts])
    step = np.diff(p_pix)
    order = None  # already sorted (as renderers often write them)
    if (step < 0).any():  # samples given in any pixel order
        order = np.lexsort((p_z, p_pix))
    elif not ((step > 0) | (p_z[1:] >= p_z[:-1])).all():  # each pixel's samples together, as a file holds them
        order = segment_argsort(p_z, np.bincount(p_pix, minlength=npix))
    if order is not None:
        p_pix, p_z, p_a, p_c = p_pix[order], p_z[order], p_a[order], p_c[order]
    start = np.ones(p_pix.size, bool)
    start[1:] = (p_pix[1:] != p_pix[:-1]) | (p_z[1:] != p_z[:-1])
    if start.all():  # no two samples of a pixel at one depth
        l_pix, l_z, l_a, l_c = p_pix, p_z, p_a, p_c
    else:
        l_a, l_c = _merge_groups(np.cumsum(start) - 1, int(start.sum()), p_a, p_c)
        l_pix, l_z = p_pix[start], p_z[start]
    l_order = np.zeros(l_a.size, np.int8)
    if vol.any():
        has_vol = np.zeros(npix, bool)
        has_vol[pixel[vol]] = True
        near = vol | (has_vol[pixel] & np.isfinite(z))  # points in a pixel with volumes split its pieces
        v_pix, v_z, v_a, v_c = _volume_layers(pixel[near], z[near], np.where(vol[near], zb[near], z[near]),
                                              a[near], c[near])
        l_pix, l_z = np.concatenate([l_pix, v_pix]), np.concatenate([l_z, v_z])
        l_a, l_c = np.concatenate([l_a, v_a]), np.concatenate([l_c, v_c])
        l_order = np.concatenate([l_order, np.ones(v_a.size, np.int8)])  # a point at b before the piece from b
        order = np.lexsort((l_order, l_z, l_pix))
        l_pix, l_z, l_a, l_c = l_pix[order], l_z[order], l_a[order], l_c[order]
    counts = np.bincount(l_pix, minlength=npix)
    trans = segment_scan(np.multiply, 1 - l_a, counts)  # transmission after each layer
    first = np.ones(l_pix.size, bool)
    first[1:] = l_pix[1:] != l_pix[:-1]
    before = np.ones_like(trans)  # transmission in front of each layer
    behind = np.flatnonzero(~first)
    before[behind] = trans[behind - 1]
    visible = before != 0  # (NaN: visible, so that it reaches the pixel)
    out_c = np.stack([np.bincount(l_pix[visible], (l_c[:, j] * before)[visible], minlength=npix)
                      for j in range(l_c.shape[1])], 1) if l_c.shape[1] else np.zeros((npix, 0))
    out_a = np.zeros(npix)
    lastrow = np.ones(l_pix.size, bool)
    lastrow[:-1] = first[1:]
    out_a[l_pix[lastrow]] = 1 - trans[lastrow]
    front = np.full(npix, np.inf)
    seen = (l_a > 0) & visible
    upix, where = np.unique(l_pix[seen], return_index=True)
    front[upix] = l_z[seen][where]
    return out_a, out_c, front, info
