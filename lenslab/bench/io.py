"""Image I/O throughput: read and write per format on a 4096 x 2048 float RGB image, as ratios against
the raw floor (numpy.tofile / numpy.fromfile of the same float32 bytes, measured in the same run), and
``convert`` throughput in images per second (2048 x 1024 float EXRs -> Hable-tone-mapped JPG) with one
job and with every core, against a plain OpenEXR + NumPy + OpenCV script doing the same work.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--quick", action="store_true",
                        help="small images (1024 x 512 and 512 x 256) for a fast smoke run")
    parser.add_argument("--repeat", type=positive_int, default=3, help="timed runs per figure; the best counts (default 3)")
    parser.add_argument("--images", type=positive_int, default=16, help="EXRs in the convert benchmark (default 16)")
    parser.add_argument("--dir", default=None, help="scratch directory (default: a temporary one)")
    parser.add_argument("--only", choices=("formats", "codecs", "convert", "deep", "gainmap"), default=None,
                        help="run only the per-format figures, the .hdr/TIFF figures against OpenCV and tifffile, "
                             "the convert figures, deep EXR reading against OpenEXR's decoding, or Ultra HDR "
                             "JPEGs read as HDR (ISO 21496-1 and XMP metadata) against their SDR base")


def _test_image(w: int, h: int):
    """A smooth HDR scene with fine noise (compresses like a real render, not like random bits)."""
    import numpy as np

    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    u, v = x / w, y / h
    rng = np.random.default_rng(0)
    base = np.stack([np.sin(6.3 * u) * np.cos(3.1 * v), np.cos(9.4 * u + 2 * v), np.sin(4 * v - 3 * u)], -1)
    img = np.exp2(3.0 * base) * 0.5
    img *= 1.0 + 0.02 * rng.standard_normal(img.shape, dtype=np.float32)
    img[int(h * 0.2):int(h * 0.25), int(w * 0.6):int(w * 0.62)] = 200.0  # a light source
    return img.astype(np.float32)


def _plain_convert(src: str, dst: str) -> None:
    """What a careful user would write by hand: the baseline the convert figures are compared with."""
    import cv2
    import numpy as np
    import OpenEXR

    ch = OpenEXR.File(src, separate_channels=True).channels()
    img = np.stack([ch[c].pixels for c in "RGB"], -1).astype(np.float32)
    a, b, c, d, e, f = 0.15, 0.50, 0.10, 0.20, 0.02, 0.30

    def hable(x):
        return (x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f) - e / f

    x = np.minimum(hable(2.0 * np.maximum(img, 0)) / hable(11.2), 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    cv2.imwrite(dst, (srgb[..., ::-1] * 255 + 0.5).astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, 95])


def run(args: argparse.Namespace) -> int:
    import warnings

    warnings.simplefilter("ignore")  # the test image's light source is beyond half range on purpose
    w, h = (1024, 512) if args.quick else (4096, 2048)
    cw, ch = (512, 256) if args.quick else (2048, 1024)
    rep = max(1, args.repeat)
    with tempfile.TemporaryDirectory(dir=args.dir) as tmp:
        d = Path(tmp)
        img = _test_image(w, h)
        raw = d / "floor.raw"
        print(f"lenslab bench io: {w} x {h} float32 RGB ({img.nbytes / 2**20:.0f} MiB), best of {rep}, "
              f"{os.cpu_count()} cores", flush=True)
        if args.only in (None, "formats"):
            _formats(d, img, raw, rep, w, h)
        if args.only in (None, "codecs"):
            _codecs(d, img, rep)
        if args.only in (None, "convert"):
            _convert(d, args, cw, ch, rep)
        if args.only in (None, "deep"):
            from lenslab.bench.deep import deep_figures

            deep_figures(d, rep)
        if args.only in (None, "gainmap"):
            from lenslab.bench.gainmap import gainmap_figures

            gainmap_figures(d, rep)
    return 0


def _formats(d: Path, img, raw: Path, rep: int, w: int, h: int) -> None:
    import numpy as np

    import lenslab.io as lio
    from lenslab.bench.timing import best_time, ratio_line

    def paired(fn, floor_fn):
        """Best times of ``fn`` and of the floor, measured alternately the same number of times, so
        that load from other processes weighs on both alike."""
        t, f = float("inf"), float("inf")
        for _ in range(rep):
            f = min(f, best_time(floor_fn, 1))
            t = min(t, best_time(fn, 1))
        return t, f

    write_floor = lambda: img.tofile(raw)  # noqa: E731
    read_floor = lambda: np.fromfile(raw, np.float32)  # noqa: E731
    ldr = np.clip(img / 8, 0, 1)
    cases = [
        ("pfm", "a.pfm", img, {}),
        ("exr half zip", "a.exr", img, {}),
        ("exr float zip", "f.exr", img, {"pixel_type": "float"}),
        ("exr half piz", "p.exr", img, {"compression": "piz"}),
        ("exr half none", "n.exr", img, {"compression": "none"}),
        ("ppm 8-bit", "a.ppm", ldr, {}),
        ("ppm 16-bit", "b.ppm", ldr, {"bits": 16}),
        ("png 8-bit", "a.png", ldr, {}),
        ("png 16-bit", "b.png", ldr, {"bits": 16}),
        ("jpg q95 4:4:4", "a.jpg", ldr, {"quality": 95}),
    ]
    write_floor()
    rows = []
    for label, name, data, opts in cases:
        tw, fw = paired(lambda: lio.write(d / name, data, **opts), write_floor)
        tr, fr = paired(lambda: lio.read(d / name), read_floor)
        rows.append((label, tw, fw, tr, fr, (d / name).stat().st_size))
    fw_all, fr_all = min(r[2] for r in rows), min(r[4] for r in rows)
    print(ratio_line("floor write  numpy.tofile", fw_all, fw_all))
    print(ratio_line("floor read   numpy.fromfile", fr_all, fr_all))
    from lenslab.bench.results import figure

    print("\nwrite, as a ratio to numpy.tofile timed alternately with it (LDR rows include sRGB encoding)")
    for label, tw, fw, _, _, size in rows:
        print(ratio_line(f"  {label}", tw, fw, f"{size / 2**20:7.1f} MiB"))
        figure(f"io.write_{_slug(label)}", f"write {label} vs numpy.tofile", tw / fw, "x", detail=True)
    print("\nread, as a ratio to numpy.fromfile timed alternately with it (LDR rows include sRGB decoding)")
    for label, _, _, tr, fr, _ in rows:
        print(ratio_line(f"  {label}", tr, fr))
        figure(f"io.read_{_slug(label)}", f"read {label} vs numpy.fromfile", tr / fr, "x", detail=True)


def _slug(label: str) -> str:
    return "_".join("".join(c if c.isalnum() else " " for c in label).split())


#: aims for lenslab's time over the reference library's on the same file (lower is better)
CODEC_AIMS = {"hdr_read": 1.5, "hdr_write": 1.5, "tiff_read": 1.3, "tiff_write": 1.3}


def _codecs(d: Path, img, rep: int) -> None:
    """Radiance .hdr against cv2.imread/imwrite and TIFF against tifffile on the same image and files.

    Ratios are lenslab's time over the library's, timed alternately (best of ``rep``); lenslab's
    figures include what the libraries leave to the caller (BGR order, float32 conversion, sRGB
    or Radiance's half-step decoding, the atomic rename).
    """
    import cv2
    import numpy as np
    import tifffile

    import lenslab.io as lio
    from lenslab.bench.results import figure, mark
    from lenslab.bench.timing import best_time

    bgr = np.ascontiguousarray(img[..., ::-1])
    cv_file, our_file = str(d / "cv.hdr"), d / "ours.hdr"
    tf_file, our_tif = d / "tf.tif", d / "ours.tif"
    cv2.imwrite(cv_file, bgr)
    lio.write(our_file, img)  # compile the run-length kernels before timing
    lio.read(our_file)
    cases = [
        ("hdr_read", "read .hdr (RLE)", lambda: lio.read(cv_file), lambda: cv2.imread(cv_file, cv2.IMREAD_UNCHANGED),
         "cv2.imread"),
        ("hdr_write", "write .hdr (RLE)", lambda: lio.write(our_file, img), lambda: cv2.imwrite(cv_file, bgr),
         "cv2.imwrite"),
        ("tiff_write", "write float32 TIFF (deflate + predictor)",
         lambda: lio.write(our_tif, img, sample_type="float"),
         lambda: tifffile.imwrite(tf_file, img, photometric="rgb", compression="adobe_deflate",
                                  predictor="floatingpoint"), "tifffile.imwrite"),
        ("tiff_read", "read float32 TIFF", lambda: lio.read(tf_file), lambda: tifffile.imread(tf_file),
         "tifffile.imread"),
    ]
    print("\n.hdr and TIFF against the libraries on the same image (lenslab time / library time)")
    for key, label, ours, theirs, name in cases:
        t, b = float("inf"), float("inf")
        for _ in range(rep):
            b = min(b, best_time(theirs, 1))
            t = min(t, best_time(ours, 1))
        ok = figure(f"io.{key}_vs_library", f"{label} vs {name}", t / b, "x", aim=CODEC_AIMS[key])
        print(f"  {label + ' vs ' + name:<58s} {t * 1e3:8.1f} ms vs {b * 1e3:8.1f} ms  {t / b:5.2f}x  "
              f"(aim {CODEC_AIMS[key]}x) {mark(ok)}")


def _convert(d: Path, args, cw: int, ch: int, rep: int) -> None:
    import numpy as np

    import lenslab.io as lio
    from lenslab.bench.results import figure
    from lenslab.bench.timing import best_time
    from lenslab.jobs.convert import ConvertJob
    from lenslab.jobs.runner import run_local

    n = max(2, args.images)
    src = d / "exrs"
    src.mkdir()
    scene = _test_image(cw, ch)
    for i in range(n):
        lio.write(src / f"img{i:03d}.exr", np.roll(scene, i * 37, axis=1), pixel_type="float")
    files = sorted(str(p) for p in src.iterdir())
    out = d / "jpgs"
    out.mkdir()
    print(f"\nconvert {n} x {cw} x {ch} float EXR (ZIP) -> Hable-tone-mapped JPG q95 (images per second)")

    fresh = iter(range(10**6))

    def new_dir() -> Path:  # every timed run writes new files, as a real batch does
        p = out / f"run{next(fresh)}"
        p.mkdir()
        return p

    def plain():
        o = new_dir()
        for f in files:
            _plain_convert(f, str(o / (Path(f).stem + ".jpg")))

    t_plain = best_time(plain, rep)
    print(f"  {'plain OpenEXR + NumPy + OpenCV script':<40s} {n / t_plain:8.2f} img/s   1.00x baseline")
    job = ConvertJob(to="jpg", tone="hable", quality=95)
    cores = os.cpu_count() or 1
    runs = [("lenslab convert --jobs 1", 1)]
    if cores > 1:
        runs += [(f"lenslab convert (default: {cores} files at once)", cores)]
    for label, jobs in runs:
        def go():
            o = new_dir()
            pairs = [(f, o / (Path(f).stem + ".jpg")) for f in files]
            res = run_local(job, pairs, jobs=jobs)
            bad = [r for r in res if r[2]]
            if bad:
                raise RuntimeError(f"convert failed: {bad[0]}")
        t = best_time(go, rep)
        print(f"  {label:<40s} {n / t:8.2f} img/s   {t_plain / t:5.2f}x baseline")
        figure(f"io.convert_jobs{jobs}_vs_script", f"{label}: EXR -> JPG speed vs a plain OpenEXR + OpenCV script",
               t_plain / t, "x", better="higher", note=f"{n / t:.2f} img/s")
