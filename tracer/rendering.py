"""Rendering an image: primary rays from a lenslab camera, traced in bands of rows, with error tracking.

Work is split into passes (groups of samples per pixel) and each pass into bands of rows, so memory
is bounded by ``batch`` samples per worker whatever the sample count (plus 44 bytes per pixel for
the image accumulators). The bands are the same in every pass (:func:`band_rows` rows each, at most
``MAX_BAND_ROWS``) and each band's random numbers come from its own generator seeded by ``(seed, pass,
first row)``: a fixed seed gives the same image whatever the number of threads, and any run of whole
bands (``rows=``, the tiles of :mod:`tracer.tiles`) renders exactly the pixels the whole image has
there. Bands run on a thread pool (NumPy and embree release the GIL).

Per-pixel mean and variance are accumulated with Welford's algorithm (merged per band with Chan et
al.'s update). ``variance`` is the estimated variance of each pixel's mean, ``M2 / (n (n - 1))``; with
stratified samples this overestimates the true variance of the mean, so error figures are
conservative. It is ``inf`` where a pixel has fewer than two samples. The image's relative error is
the root mean square of the per-pixel standard errors over the mean pixel value.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field

import numpy as np

from tracer.accel import cpu_count
from tracer.integrators import INTEGRATORS, trace
from tracer.lensfx import apply_lens_effects, has_effects

DEFAULT_BATCH = 1 << 17  # samples per band: bounds the memory of a worker (about 40 MB)
STEP_SPP = 16  # samples per pass when stopping on a time budget or a target error
MAX_BAND_ROWS = 8  # rows per band at most: small images still split into bands (threads, tiles)


@dataclass
class RenderResult:
    """A rendered frame. ``image`` and ``variance`` are float32 ``H x W x 3``; ``alpha`` is ``H x W``
    (the fraction of each pixel's samples that the lens maps to a ray; ``image`` is premultiplied by it)."""

    image: np.ndarray
    variance: np.ndarray
    alpha: np.ndarray
    spp: int
    seconds: float
    camera: object = None
    integrator: str = "path"
    max_depth: int = 8
    seed: int | None = 0
    stopped_by: str = "spp"
    info: dict = field(default_factory=dict)

    @property
    def valid(self) -> np.ndarray:
        return self.alpha > 0

    @property
    def relative_error(self) -> float:
        return relative_error(self.image, self.variance)

    @property
    def rgba(self) -> np.ndarray:
        return np.concatenate([self.image, self.alpha[..., None]], axis=-1).astype(np.float32)

    @property
    def attributes(self) -> dict:
        """How the frame was made, as EXR header attributes."""
        return {
            "tracer.scene": str(self.info.get("scene", "")), "tracer.integrator": self.integrator,
            "tracer.max_depth": int(self.max_depth), "tracer.spp": int(self.spp),
            "tracer.seed": "none" if self.seed is None else str(self.seed), "tracer.seconds": float(self.seconds),
            "tracer.relative_error": float(self.relative_error), "tracer.stopped_by": self.stopped_by,
        }

    def save(self, path, variance_path=None, overwrite: bool = True):
        """Write the image (RGBA where some pixels lie outside the lens) with its camera; optionally the variance."""
        from tracer.imageio import write_image

        out = None
        if path is not None:
            image = self.rgba if float(self.alpha.min()) < 1 else self.image
            out = write_image(path, image, camera=self.camera, overwrite=overwrite, attributes=self.attributes)
        if variance_path is not None:
            write_image(variance_path, self.variance, camera=self.camera, overwrite=overwrite,
                        attributes={**self.attributes, "tracer.content": "variance of each pixel's mean"})
        return out


def relative_error(image: np.ndarray, variance: np.ndarray) -> float:
    """RMS over pixels of the standard error of each pixel's mean, over the mean pixel value."""
    mean = float(np.mean(image))
    if not np.all(np.isfinite(variance)):
        return float("inf")
    if mean <= 0:
        return 0.0 if float(np.max(variance)) == 0 else float("inf")
    return float(np.sqrt(np.mean(variance)) / mean)


def _next_pass(done: int, spp: int, width: int, batch: int, elapsed: float, time_budget: float | None,
               adaptive: bool) -> int:
    """Samples per pixel of the next pass (0: stop).

    Without a stopping rule, as few passes as the memory bound allows. With one, a first pass of two
    samples (the fewest that give a variance), then passes sized from the measured speed to end near
    the time budget and to check the error often, at most ``STEP_SPP``.
    """
    left = spp - done
    cap = max(1, batch // max(1, width))
    if left <= 0:
        return 0
    if not adaptive:
        return min(left, cap)
    if done == 0:
        return min(left, 2, cap)
    step = min(left, cap, STEP_SPP)
    if time_budget is not None:
        remaining = time_budget - elapsed
        if remaining <= 0:
            return 0
        per_spp = elapsed / done
        fits = int(remaining / per_spp) if per_spp > 0 else step
        if fits < 1:
            return 0
        step = min(step, fits)
    return step


def band_rows(width: int, spp: int, batch: int = DEFAULT_BATCH, adaptive: bool = False) -> int:
    """Rows per band, the same in every pass: the largest pass's samples of a band fit in ``batch``."""
    cap = max(1, batch // max(1, width))
    largest = min(int(spp), cap, STEP_SPP) if adaptive else min(int(spp), cap)
    return int(min(MAX_BAND_ROWS, max(1, batch // (max(1, width) * largest))))


def _sub_seed(seed: int | None, *keys: int) -> int:
    return int(np.random.SeedSequence([0 if seed is None else int(seed), *keys]).generate_state(1)[0])


def render(scene, camera, spp: int = 16, seed: int | None = 0, integrator: str = "path", max_depth: int = 8,
           progress: bool = False, time_budget: float | None = None, target_error: float | None = None,
           threads: int | None = None, batch: int = DEFAULT_BATCH, rr_depth: int = 3,
           rows: tuple[int, int] | None = None) -> RenderResult:
    """Render ``scene`` through ``camera`` (a :class:`lenslab.lenses.Camera`).

    ``spp`` samples per pixel is the maximum when ``time_budget`` (seconds) or ``target_error`` (relative
    standard error of the image, see :func:`relative_error`) is given: the render then runs in passes
    sized from its measured speed, ends when the next pass would not fit in the budget or once the error
    is reached (the first pass, two samples per pixel, always runs), and says why in ``stopped_by``.
    ``seed=None`` puts the sub-pixel samples at the strata centres (a fixed grid; path sampling still
    uses seed 0), which with ``integrator="direct"`` and point lights gives noise-free images.
    ``threads`` defaults to every core; ``batch`` bounds the samples traced at once per thread.
    ``rows=(r0, r1)`` renders those rows only (``r0`` a multiple of :func:`band_rows`): the result holds
    ``r1 - r0`` rows, bit for bit the same as those rows of the whole image (not with a stopping rule).
    """
    if isinstance(scene, str):
        from tracer.load import load_scene

        scene = load_scene(scene)
    if integrator not in INTEGRATORS:
        raise ValueError(f"unknown integrator {integrator!r}; use one of {', '.join(INTEGRATORS)}")
    spp = int(spp)
    if spp < 1:
        raise ValueError(f"spp must be at least 1, got {spp}")
    if time_budget is not None and not time_budget > 0:
        raise ValueError(f"time budget must be positive seconds, got {time_budget}")
    if target_error is not None and not target_error > 0:
        raise ValueError(f"target error must be positive, got {target_error}")
    threads = cpu_count() if threads is None else max(1, int(threads))
    width, full_height = camera.width, camera.height
    adaptive = time_budget is not None or target_error is not None
    rows_per_band = band_rows(width, spp, batch, adaptive)
    top, bottom = (0, full_height) if rows is None else (int(rows[0]), int(rows[1]))
    if not (0 <= top < bottom <= full_height) or top % rows_per_band or (
            bottom % rows_per_band and bottom != full_height):
        raise ValueError(f"rows {rows} are not whole bands of {rows_per_band} rows of a {full_height}-row image")
    if rows is not None and adaptive:
        raise ValueError("a time budget or a target error needs the whole image, not a run of rows")
    height = bottom - top  # the accumulators hold these rows; band row r0 is image row top + r0
    scene.accel  # build the accelerator before the clock starts

    # per-pixel accumulators: the mean in float64, the rest in float32 (counts are exact to 2^24 samples)
    count = np.zeros((height, width), dtype=np.float32)
    mean = np.zeros((height, width, 3), dtype=np.float64)
    m2 = np.zeros((height, width, 3), dtype=np.float32)
    valid = np.zeros((height, width), dtype=np.float32)

    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=spp * width * height, unit="spl", unit_scale=True, file=sys.stderr,
                   disable=not sys.stderr.isatty(), leave=False, desc=f"tracing {scene.name}")

    effects = has_effects(camera.lens)

    def band(pass_no: int, pass_spp: int, r0: int, r1: int) -> int:
        grid_seed = None if seed is None else _sub_seed(seed, pass_no)
        o, d, ok = camera.rays(samples=pass_spp, seed=grid_seed, rows=slice(top + r0, top + r1))
        h = r1 - r0
        o, d, ok = o.reshape(-1, 3), d.reshape(-1, 3), ok.reshape(-1)
        rng = np.random.default_rng([0 if seed is None else int(seed), pass_no, top + r0, 1])
        if ok.all():
            radiance = trace(scene, o, d, rng, integrator, max_depth, rr_depth, threads=1)
        else:
            radiance = np.zeros((len(ok), 3), dtype=np.float32)
            k = np.flatnonzero(ok)
            if len(k):
                radiance[k] = trace(scene, np.take(o, k, axis=0), np.take(d, k, axis=0), rng, integrator, max_depth,
                                    rr_depth, threads=1)
        if effects:  # a ray per colour channel (chromatic aberration) and the vignetting weight
            xy = camera.pixel_grid(slice(top + r0, top + r1), pass_spp, grid_seed).reshape(-1, 2)
            radiance = apply_lens_effects(scene, camera, xy, radiance, rng, integrator, max_depth, rr_depth)
        x = radiance.reshape(h, width, pass_spp, 3)
        b_mean = x.mean(axis=2, dtype=np.float64)
        dev = x - b_mean[:, :, None].astype(np.float32)
        b_m2 = np.einsum("hwsc,hwsc->hwc", dev, dev, dtype=np.float64)
        n_a = count[r0:r1, :, None].astype(np.float64)
        n_b = float(pass_spp)
        n = n_a + n_b
        delta = b_mean - mean[r0:r1]
        mean[r0:r1] += delta * (n_b / n)
        m2[r0:r1] += b_m2 + delta * delta * (n_a * n_b / n)
        count[r0:r1] += n_b
        valid[r0:r1] += ok.reshape(h, width, pass_spp).sum(axis=2)
        return h * width * pass_spp  # samples traced: the main thread moves the bar

    start = time.perf_counter()
    stopped_by = "spp"
    done = 0
    pass_no = 0
    with ThreadPoolExecutor(max_workers=threads) as ex:
        while True:
            elapsed = time.perf_counter() - start
            pass_spp = _next_pass(done, spp, width, batch, elapsed, time_budget, adaptive)
            if pass_spp == 0:
                if done < spp:
                    stopped_by = "time"
                break
            jobs = []
            try:  # Ctrl-C may land anywhere in here, in the middle of starting a pool thread too
                for r0 in range(0, height, rows_per_band):
                    jobs.append(ex.submit(band, pass_no, pass_spp, r0, min(height, r0 + rows_per_band)))
                for j in as_completed(jobs):
                    traced = j.result()
                    if bar is not None:  # drawn by this thread only: none draws it once it is closed
                        bar.update(traced)
            except BaseException:  # an error or Ctrl-C: drop the bands not started yet
                for j in jobs:
                    j.cancel()
                # the queue is emptied too: a pool thread whose start the interrupt cut short (the pool does
                # not join it) ends after its band
                ex.shutdown(wait=True, cancel_futures=True)
                if bar is not None:
                    bar.close()
                raise
            done += pass_spp
            pass_no += 1
            if target_error is not None and done >= 2 and done < spp:
                n = count.astype(np.float64)[..., None]
                var = m2 / (n * (n - 1))
                if relative_error(mean, var) <= target_error:
                    stopped_by = "error"
                    break
    seconds = time.perf_counter() - start
    if bar is not None:
        bar.close()
    with np.errstate(divide="ignore", invalid="ignore"):
        n = count.astype(np.float64)[..., None]
        variance = np.where(n >= 2, m2 / (n * (n - 1)), np.inf)
    return RenderResult(
        image=mean.astype(np.float32), variance=variance.astype(np.float32),
        alpha=(valid / np.maximum(count, 1)).astype(np.float32), spp=done, seconds=seconds, camera=camera,
        integrator=integrator, max_depth=max_depth, seed=seed, stopped_by=stopped_by,
        info={"samples_per_second": done * width * height / max(seconds, 1e-12), "threads": threads,
              "scene": scene.name},
    )


def trace_pixels(scene, camera, xy, spp: int = 1, seed: int | None = 0, integrator: str = "path",
                 max_depth: int = 8, rr_depth: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Radiance through given continuous pixel positions ``xy`` (``(N, 2)``), ``spp`` paths each.

    The rays come from ``camera.pixel_to_world`` (the lens's own maths). Returns the mean radiance
    ``(N, 3)``, the variance of that mean ``(N, 3)`` (``inf`` with one sample) and validity ``(N,)``.
    """
    if isinstance(scene, str):
        from tracer.load import load_scene

        scene = load_scene(scene)
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    o, d, ok = camera.pixel_to_world(xy)
    n = len(xy)
    rng = np.random.default_rng([0 if seed is None else int(seed), 2])
    rep = np.repeat(np.nonzero(ok)[0], spp)
    x = np.zeros((n, spp, 3), dtype=np.float64)
    if len(rep):
        x[ok] = trace(scene, o[rep], d[rep], rng, integrator, max_depth, rr_depth).reshape(-1, spp, 3)
    if has_effects(camera.lens):  # a ray per colour channel and the vignetting weight, as in render()
        xs = np.repeat(xy, spp, axis=0)
        x = apply_lens_effects(scene, camera, xs, x.reshape(-1, 3), rng, integrator, max_depth,
                               rr_depth).reshape(n, spp, 3)
    mean = x.mean(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        var = x.var(axis=1, ddof=1) / spp if spp > 1 else np.full((n, 3), np.inf)
    return mean.astype(np.float32), np.asarray(var, dtype=np.float32), ok
