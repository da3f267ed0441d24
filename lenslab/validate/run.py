"""Validation of warps against direct renders, and the speed/accuracy table.

For a target camera the steps are:

1. render the **reference** directly through the target camera (many samples per pixel);
2. render an equirect **panorama** from the same eye at each requested size;
3. **warp** each panorama into the target camera with each setting (filter, sub-samples, antialias),
   timing the best of a few runs;
4. optionally render the target directly at a few low sample counts (the **direct** rows), the
   alternative the panorama route competes with;
5. compare everything with the reference (:func:`lenslab.metrics.compare`): overall, on the edges and
   away from them, next to the reference's own noise floor.

The result is a :class:`Validation`: a list of JSON-friendly rows (one per setting) and the images
needed for plots. :mod:`lenslab.validate.report` writes it out.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from lenslab import metrics
from lenslab.errors import LenslabError, WarpError
from lenslab.filters import FILTERS
from lenslab.lenses import Camera, Pose, make_lens



class ValidationError(LenslabError, ValueError):
    """A validation cannot be set up as asked (bad setting string, sizes, or an unsupported camera)."""


@dataclass(frozen=True)
class WarpSetting:
    """One way of warping: a filter, sub-samples per output pixel and the footprint prefilter."""

    filter: str = "bilinear"
    samples: int = 1
    antialias: bool = False

    @property
    def label(self) -> str:
        s = self.filter
        if self.antialias:
            s = "antialias" if self.filter == "bilinear" else f"{s}+antialias"
        if self.samples > 1:
            k = int(round(math.sqrt(self.samples)))
            s += f"@{k}x{k}" if k * k == self.samples else f"@{self.samples}"
        return s

    @classmethod
    def parse(cls, token: str) -> "WarpSetting":
        """``bilinear``, ``lanczos``, ``antialias`` (bilinear with the footprint prefilter, which replaces
        the filter: ``bicubic+antialias`` is refused), and ``@N`` or ``@KxK`` for sub-samples: ``bilinear@2x2``."""
        tok = token.strip().lower()
        if not tok:
            raise ValidationError("empty warp setting; use e.g. bilinear, lanczos, antialias or bilinear@2x2")
        body, _, samp = tok.partition("@")
        samples = 1
        if samp:
            try:
                if "x" in samp:
                    a, b = samp.split("x")
                    samples = int(a) * int(b)
                else:
                    samples = int(samp)
            except ValueError:
                raise ValidationError(f"warp setting {token!r}: sub-samples must be N or KxK, got {samp!r}") from None
            if samples < 1:
                raise ValidationError(f"warp setting {token!r}: sub-samples must be at least 1")
        parts = [p for p in body.split("+") if p]
        antialias = False
        filt = "bilinear"
        for p in parts:
            if p in ("antialias", "aa"):
                antialias = True
            elif p in FILTERS:
                filt = FILTERS.canonical(p)
            else:
                raise ValidationError(
                    f"warp setting {token!r}: unknown filter {p!r}; use one of {', '.join(FILTERS)} or antialias")
        from lenslab.errors import WarpError
        from lenslab.filters import check_filter_with_antialias

        try:
            check_filter_with_antialias(filt, antialias, ("the filter", "antialias"))
        except WarpError as exc:
            raise ValidationError(f"warp setting {token!r}: {exc}") from None
        return cls(filt, samples, antialias)


def parse_size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValidationError(f"size {text!r} is not WIDTHxHEIGHT (e.g. 2048x1024)") from None
    if w < 1 or h < 1:
        raise ValidationError(f"size {text!r} must be positive")
    return w, h


def panorama_camera(target: Camera, size: tuple[int, int]) -> Camera:
    """An equirect camera at the target's eye, world-aligned (the warp handles the rotation)."""
    eyes = np.asarray(target.lens.eye_offsets, dtype=np.float64)
    if len(np.unique(np.round(eyes, 12), axis=0)) > 1:
        raise WarpError(
            f"the target lens {target.lens.spec()} has {len(eyes)} different eye points; one panorama "
            "holds one eye, so its views would carry parallax error. Give every tile the same eye, or "
            "validate each tile on its own.")
    eye = target.pose.eye + eyes[0] @ target.pose.rotation.T
    return Camera(make_lens("equirect", size), Pose(np.eye(3), eye))


def default_warp() -> Callable:
    from lenslab.warp import warp

    return warp


def call_warp(warp_fn: Callable, image, src: Camera, dst: Camera, setting: WarpSetting):
    out = warp_fn(image, src, dst, filter=setting.filter, samples=setting.samples, antialias=setting.antialias)
    img, alpha = out
    img = np.asarray(img, dtype=np.float32)
    alpha = np.asarray(alpha, dtype=np.float32)
    if alpha.ndim == 3:
        alpha = alpha[..., 0]
    if img.ndim == 3 and img.shape[-1] == 4:
        img = img[..., :3]
    return img, alpha


def edges_for(reference, radius: int = 2, shadows: bool = True) -> tuple[np.ndarray, str]:
    """Edge mask of a reference render and a sentence saying where it came from.

    With geometric AOVs (depth / normal / prim_id) the edges are their discontinuities, plus the lens
    rim; ``shadows=True`` adds strong gradients of the denoised reference image, for shadow edges the
    AOVs do not mark. Without AOVs only the image gradients (and the rim) are used.
    """
    valid = metrics.valid_mask(reference.alpha)
    aovs = {k: reference.aovs.get(k) for k in ("depth", "normal", "prim_id")}
    have = [k for k, v in aovs.items() if v is not None]
    if have:
        e = metrics.edge_mask_from_aovs(radius=radius, depth_tolerance=0.1, normal_tolerance_deg=10.0, **aovs)
        e |= metrics.dilate(~valid, radius)
        how = f"geometric discontinuities ({', '.join(have)} AOVs at pixel centres) and the lens rim"
        if shadows:
            e |= metrics.edge_mask_from_image(reference.image, radius=radius, mask=valid)
            how += ", plus strong gradients of the denoised reference's log luminance (shadow edges)"
        return e, f"pixels within {radius} px of " + how
    e = metrics.edge_mask_from_image(reference.image, radius=radius, mask=valid)
    return e, (f"pixels within {radius} px of strong gradients of the denoised reference's log luminance "
               "(the renderer gave no geometric AOVs) and of the lens rim")


@dataclass
class Validation:
    """Everything one validation measured (rows) and the images the report plots."""

    meta: dict[str, Any]
    reference: Any                       # sources.Render
    edges: np.ndarray
    rows: list[dict[str, Any]] = field(default_factory=list)
    images: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)  # label -> (img, alpha)

    def warp_rows(self) -> list[dict[str, Any]]:
        return [r for r in self.rows if r["kind"] == "warp"]

    def to_json(self) -> dict[str, Any]:
        return {"meta": self.meta, "rows": self.rows, "pareto": pareto_front(self.rows)}


def pareto_front(rows: Sequence[dict[str, Any]], time_key: str = "seconds", error_key: str = "l1") -> list[str]:
    """Labels of the rows no other row beats in both time and error (sorted by time)."""
    pts = [(r[time_key], r[error_key], r["label"]) for r in rows
           if np.isfinite(r.get(error_key, np.nan)) and np.isfinite(r.get(time_key, np.nan))]
    pts.sort()
    front, best = [], float("inf")
    for t, e, lab in pts:
        if e < best:
            front.append(lab)
            best = e
    return front


def _timed_warp(warp_fn, image, src, dst, setting, repeat: int):
    best, out = float("inf"), None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = call_warp(warp_fn, image, src, dst, setting)
        best = min(best, time.perf_counter() - t0)
    return out, best


def _split_render(source, target: Camera, spp: int, seed: int):
    """The mean of two independent renders of ``spp / 2`` samples each, and the two halves."""
    half = max(1, spp // 2)
    a = source.render(target, spp=half, seed=seed)
    b = source.render(target, spp=half, seed=seed + 7919)
    mean = a
    img = 0.5 * (a.image.astype(np.float64) + b.image)
    alpha = 0.5 * (a.alpha.astype(np.float64) + b.alpha)
    stderr = None
    if a.stderr is not None and b.stderr is not None:
        stderr = (0.5 * np.sqrt(a.stderr.astype(np.float64) ** 2 + b.stderr.astype(np.float64) ** 2)).astype(np.float32)
    mean = type(a)(img.astype(np.float32), alpha.astype(np.float32), stderr, a.aovs, a.seconds + b.seconds,
                   2 * half, dict(a.info, halves=True))
    return mean, (a.image, b.image)


def render_reference(source, target: Camera, spp: int | None, error: float | None, seed: int | None,
                     max_spp: int = 4096):
    """Render the reference; returns ``(render, halves)``.

    With ``seed=None`` (noise-free) it renders once with ``spp`` samples (``halves`` is None). Monte Carlo references
    are the mean of two independent half renders (``halves``, for the empirical noise floor). With
    ``error``, a pilot render at ``spp`` (default 16) measures the noise floor, which falls as
    ``1/sqrt(spp)``, and the reference gets ``spp * (floor / error)^2`` samples (at most ``max_spp``).
    """
    spp = int(spp or (64 if error is None else 16))
    if seed is None:  # fixed sample positions: nothing to estimate
        return source.render(target, spp=spp, seed=None), None
    ref, halves = _split_render(source, target, spp, seed)
    if error is None:
        return ref, halves
    m = metrics.valid_mask(ref.alpha)
    floor = metrics.noise_floor_split(halves[0], halves[1], m)
    if not np.isfinite(floor) or floor <= error:
        return ref, halves
    need = min(max_spp, int(math.ceil(spp * (floor / error) ** 2)))
    if need <= spp:
        return ref, halves
    pilot = ref.seconds
    ref, halves = _split_render(source, target, need, seed + 1)
    ref.seconds += pilot  # the pilot render is part of the cost
    return ref, halves


def validate(source, target: Camera, pano_sizes: Sequence[tuple[int, int]], settings: Sequence[WarpSetting],
             spp: int = 1, reference_spp: int | None = 64, reference_error: float | None = None,
             seed: int | None = 0, direct_spp: Sequence[int] = (), repeat: int = 3,
             warp_fn: Callable | None = None, edge_radius: int = 2, with_flip: bool = True,
             progress: bool = True, keep_images: bool = True) -> Validation:
    """Measure every (panorama size, warp setting) against a direct render of ``target``.

    ``source`` is a :mod:`lenslab.validate.sources` source. In noise-free mode (a noise-free source,
    or ``seed=None`` with a deterministic scene) every render uses fixed sample positions, so the errors
    are the resampling error alone. Each row holds its label, the panorama size, the setting, the
    seconds of the panorama render, of the warp (best of ``repeat``) and their sum, and every metric.
    """
    from tqdm import tqdm

    warp_fn = warp_fn or default_warp()
    settings = list(settings)
    if not settings:
        raise ValidationError("no warp settings to validate; give at least one filter")
    noise_free = bool(getattr(source, "noise_free", False)) or seed is None
    rseed = None if noise_free else (None if seed is None else seed + 1_000_003)
    pseed = None if noise_free else seed

    total = 1 + len(pano_sizes) * (1 + len(settings)) + len(direct_spp)
    bar = tqdm(total=total, desc="validate", unit="step", disable=not progress, leave=False)

    ref, halves = render_reference(source, target, reference_spp, reference_error, rseed)
    bar.update()
    edges, edge_source = edges_for(ref, edge_radius, getattr(source, "shadow_edges", True))
    mask = metrics.valid_mask(ref.alpha)
    ref_noise = None
    if halves is not None:
        ref_noise = {"l1": metrics.noise_floor_split(halves[0], halves[1], mask), "method": "two halves"}
    elif ref.stderr is not None:
        ref_noise = {"l1": metrics.noise_floor(ref.image, ref.stderr, mask)["l1"], "method": "zero (noise-free)"}

    meta = {
        "source": getattr(source, "name", type(source).__name__),
        "target": target.lens.spec(),
        "size": list(target.size),
        "pose": target.pose.to_dict(),
        "mode": "noise-free" if noise_free else "monte-carlo",
        "panorama_spp": int(spp),
        "reference": {"spp": int(ref.spp), "seconds": ref.seconds,
                      "noise_l1": None if ref_noise is None else ref_noise["l1"],
                      "noise_method": None if ref_noise is None else ref_noise["method"]},
        "edges": edge_source,
        "edge_share": float(edges[mask].mean()) if mask.any() else float("nan"),
        "metric_notes": "l1 = sum|t-r|/sum|r| over pixels fully covered in both images; "
                        "_edge/_interior split by the edge mask; noise_l1 = expected l1 of the "
                        "reference's own noise; excess_l1 = l1 - noise_l1",
    }
    val = Validation(meta, ref, edges)

    def measure(img, alpha):
        return metrics.compare(ref.image, img, ref.alpha, alpha, edges=edges, ref_stderr=ref.stderr,
                               with_flip=with_flip, ref_halves=halves)

    for size in pano_sizes:
        pcam = panorama_camera(target, size)
        pano = source.render(pcam, spp=spp, seed=pseed)
        bar.update()
        for st in settings:
            (img, alpha), wsec = _timed_warp(warp_fn, pano.image, pcam, target, st, repeat)
            label = f"{size[0]}x{size[1]} {st.label}"
            row = {"kind": "warp", "label": label, "pano_size": list(size), "filter": st.filter,
                   "samples": st.samples, "antialias": st.antialias, "setting": st.label,
                   "spp": int(spp), "trace_seconds": pano.seconds, "warp_seconds": wsec,
                   "seconds": pano.seconds + wsec}
            row.update(measure(img, alpha))
            val.rows.append(row)
            if keep_images:
                val.images[label] = (img, alpha)
            bar.update()
    for n in direct_spp:
        d = source.render(target, spp=int(n), seed=pseed)
        label = f"direct {n} spp"
        row = {"kind": "direct", "label": label, "pano_size": None, "filter": None, "samples": int(n),
               "antialias": False, "setting": "direct", "spp": int(n), "trace_seconds": d.seconds,
               "warp_seconds": 0.0, "seconds": d.seconds}
        row.update(measure(d.image, d.alpha))
        val.rows.append(row)
        if keep_images:
            val.images[label] = (d.image, d.alpha)
        bar.update()
    bar.close()
    return val


@dataclass
class Verdict:
    """Whether a warp passed validation, and why not."""

    ok: bool
    reasons: list[str]

    def __bool__(self) -> bool:
        return self.ok

    def __str__(self) -> str:
        return "pass" if self.ok else "FAIL: " + "; ".join(self.reasons)


def check(result: dict[str, Any], interior: float = 0.01, overall: float = 0.02,
          noise_allowance: float = 1.0) -> Verdict:
    """Pass when the relative L1 away from edges is at most ``interior`` and overall at most ``overall``.

    ``result`` is a row or a :func:`lenslab.metrics.compare` dict. Each bound is raised by
    ``noise_allowance`` times the reference's own expected noise L1 (if known), so a noisy reference
    does not fail a correct warp.
    """
    reasons = []
    for key, bound in (("l1_interior", interior), ("l1", overall)):
        value = result.get(key)
        if value is None:
            if key == "l1_interior":
                continue  # no edge mask given: only the overall bound applies
            reasons.append(f"no {key} measured")
            continue
        noise = result.get("noise_" + key)
        limit = bound + (noise_allowance * noise if noise is not None and np.isfinite(noise) else 0.0)
        if not np.isfinite(value) or value > limit:
            reasons.append(f"{key} = {100 * value:.3f}% > {100 * limit:.3f}%")
    return Verdict(not reasons, reasons)
