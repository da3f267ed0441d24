"""Reading Ultra HDR JPEGs as their HDR rendition (``lenslab bench io --only gainmap``): the CPU time (every
thread's: ``time.process_time``) of ``lenslab.read`` on a 4080 x 3072 file whose only gain map metadata is the
ISO 21496-1 block (written here by libultrahdr through imagecodecs, a 1020 x 768 gain map as a phone writes),
and on the Pixel photo of the shared corpus (``formats/oiio-images/ultrahdr_sky.jpg``: the same size, ``hdrgm``
XMP), each against reading its own SDR base image (``FILE:sdr``) timed alternately with it; best of N.
"""

from __future__ import annotations

import time
from pathlib import Path

#: the Pixel photo of the shared corpus, beside this checkout
SKY = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "formats" / "oiio-images" / "ultrahdr_sky.jpg"
WIDTH, HEIGHT = 4080, 3072


def _cpu(fn) -> float:
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def _iso_file(d: Path) -> Path:
    """A 4080 x 3072 photo-like HDR scene (highlights to 2^6 times SDR white) as libultrahdr's Ultra HDR JPEG."""
    import imagecodecs
    import numpy as np

    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float32)
    u, v = x / WIDTH, y / HEIGHT
    rgb = np.stack([np.sin(6.3 * u) * np.cos(3.1 * v), np.cos(9.4 * u + 2 * v), np.sin(4 * v - 3 * u)], -1)
    image = np.ones((HEIGHT, WIDTH, 4), np.float16)
    image[..., :3] = np.exp2(3.0 * rgb + (3.0 * (u > 0.8) * (v < 0.2))[..., None]) * 0.25
    path = d / "iso21496.jpg"
    path.write_bytes(imagecodecs.ultrahdr_encode(image, scale=4))
    return path


def gainmap_figures(d: Path, rep: int) -> None:
    import warnings

    import lenslab.io as lio
    from lenslab.bench.results import figure

    files = [("ISO 21496-1 (libultrahdr)", "iso", _iso_file(d))]
    if SKY.is_file():
        files.append(("hdrgm XMP (Pixel photo)", "xmp", SKY))
    else:
        print(f"\n(no {SKY}: the XMP photo's figures are left out)")
    print(f"\nUltra HDR JPEG {WIDTH} x {HEIGHT} read as HDR, CPU seconds (all threads), best of {rep}, each file's "
          "HDR and SDR reads interleaved")
    best: dict[tuple[str, str], float] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(rep):
            for _, key, path in files:
                for kind, name in (("sdr", f"{path}:sdr"), ("hdr", str(path))):
                    t = _cpu(lambda: lio.read(name))
                    best[key, kind] = min(best.get((key, kind), float("inf")), t)
    for label, key, _ in files:
        hdr, sdr = best[key, "hdr"], best[key, "sdr"]
        print(f"  {label:<28s} HDR {hdr:6.3f} s   SDR base {sdr:6.3f} s   {hdr / sdr:5.2f}x")
        figure(f"io.gainmap_{key}_hdr_vs_sdr", f"read {label} as HDR vs its SDR base (CPU)", hdr / sdr, "x",
               note=f"{hdr:.3f} s against {sdr:.3f} s of CPU")
    if len(files) == 2:
        ratio = best["iso", "hdr"] / best["xmp", "hdr"]
        print(f"  ISO file's HDR read over the XMP photo's: {ratio:5.2f}x")
        figure("io.gainmap_iso_vs_xmp", "read the ISO 21496-1 file as HDR vs the XMP photo (CPU)", ratio, "x",
               note=f"{best['iso', 'hdr']:.3f} s against {best['xmp', 'hdr']:.3f} s of CPU")
