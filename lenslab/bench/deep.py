"""Reading deep EXR files: ``lenslab.read`` (count tables, OpenEXR's decoding, gathering, flattening) as
a ratio to OpenEXR's own decoding of the same file (``OpenEXR.File(path)``, the floor: lenslab decodes
through it) and to OpenImageIO's read and ``ImageBufAlgo.flatten`` (where installed), timed alternately.

Two files written here: ``sparse`` is shaped like OpenEXR's ``Trunks.exr`` test image (1920 x 814, a
tenth of the pixels with one or two samples), ``dense`` a render with 4 samples a pixel on average in no
order (1024 x 512, 0 to 8 per pixel).
"""

from __future__ import annotations

from pathlib import Path


def _deep_file(path: Path, w: int, h: int, counts) -> Path:
    import numpy as np
    import OpenEXR

    rng = np.random.default_rng(5)
    counts = counts.reshape(-1)
    total = int(counts.sum())
    z = rng.uniform(1, 100, total).astype(np.float32)
    a = rng.uniform(0.05, 1, total).astype(np.float16)
    rgb = (a[:, None].astype(np.float32) * rng.uniform(0, 1, (total, 3))).astype(np.float16)
    cuts = np.cumsum(counts)[:-1]
    chans = {n: np.empty(w * h, dtype=object) for n in ("R", "G", "B", "A", "Z")}
    filled = np.flatnonzero(counts)
    for name, values in (("Z", z), ("A", a), ("R", rgb[:, 0]), ("G", rgb[:, 1]), ("B", rgb[:, 2])):
        pieces = np.split(values, cuts)
        target = chans[name]
        for i in filled.tolist():  # (setting up the file; the reader has no such loop)
            target[i] = pieces[i]
    header = {"compression": OpenEXR.ZIPS_COMPRESSION, "type": OpenEXR.deepscanline}
    OpenEXR.File(header, {n: c.reshape(h, w) for n, c in chans.items()}).write(str(path))
    return path


def deep_figures(d: Path, rep: int) -> None:
    import warnings

    import numpy as np
    import OpenEXR

    import lenslab.io as lio
    from lenslab.bench.results import figure
    from lenslab.bench.timing import best_time, ratio_line

    rng = np.random.default_rng(1)
    files = {
        "sparse": _deep_file(d / "sparse.exr", 1920, 814,
                             np.where(rng.random(1920 * 814) < 0.1, rng.integers(1, 3, 1920 * 814), 0)),
        "dense": _deep_file(d / "dense.exr", 1024, 512, rng.integers(0, 9, 1024 * 512)),
    }
    try:
        import OpenImageIO as oiio
    except ImportError:
        oiio = None
    print("\ndeep EXR read (flattened), as a ratio to OpenEXR's decoding of the same file, timed alternately")
    for label, path in files.items():
        def ours():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                lio.read(path)

        def floor():
            OpenEXR.File(str(path))

        def theirs():
            oiio.ImageBufAlgo.flatten(oiio.ImageBuf(str(path)))

        t = f = o = float("inf")
        for _ in range(rep):
            f = min(f, best_time(floor, 1))
            t = min(t, best_time(ours, 1))
            if oiio is not None:
                o = min(o, best_time(theirs, 1))
        samples = lio.read(path)[1]["deep"]["samples"]
        print(ratio_line(f"  {label} ({samples} samples)", t, f, f"OpenEXR decode {f * 1e3:.0f} ms"))
        figure(f"io.read_deep_{label}", f"read deep ({label}) vs OpenEXR decode", t / f, "x", detail=True)
        figure(f"io.read_deep_{label}_seconds", f"read deep ({label})", t, "s", detail=True)
        if oiio is not None:
            print(ratio_line(f"  {label} vs OpenImageIO read+flatten", t, o))
            figure(f"io.read_deep_{label}_vs_oiio", f"read deep ({label}) vs OpenImageIO flatten", t / o, "x",
                   detail=True)
