"""TIFF: float32, half, 16- and 8-bit grey or RGB, with alpha, through tifffile (codec: :mod:`lenslab.io.tiff`)."""

from __future__ import annotations

from lenslab.io.plugin import Format


def _read(path, selector=None, raw=False):
    from lenslab.io.tiff import read_tiff

    return read_tiff(path, raw=raw)


def _write(tmp, image, **options):
    from lenslab.io.tiff import write_tiff

    write_tiff(tmp, image, **options)


def _declare(path, **options):
    from lenslab.io.tiff.layout import declare_tiff

    return declare_tiff(path, **options)


#: pages a probe describes (a stack of thousands is counted, its first pages described)
PAGES_LISTED = 16


def _probe(path) -> dict:
    """The first :data:`PAGES_LISTED` pages: shape, axes, dtype, compression, photometric, planar configuration,
    extra samples; and how many pages the file holds (``page_count``)."""
    import itertools

    import tifffile

    from lenslab.io.tiff import tifffile_notes

    tifffile_notes()
    with tifffile.TiffFile(path) as tif:
        return {"pages": [{"shape": list(page.shape), "axes": page.axes, "dtype": str(page.dtype),
                           "compression": page.compression.name.lower(), "photometric": page.photometric.name.lower(),
                           "planar": "separate" if int(page.planarconfig) == 2 else "contig",
                           "extrasamples": [int(v) for v in page.extrasamples]}
                          for page in itertools.islice(tif.pages, PAGES_LISTED)],
                "page_count": len(tif.pages)}


FORMATS = (Format(
    name="tiff", title="TIFF", extensions=(".tif", ".tiff"),
    magic=lambda head: head[:4] in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"),
    hdr=True, alpha=True, channels=(1, 2, 3, 4), bit_depths=(8, 16, 32), sample_types=("uint", "half", "float"),
    read=_read, declare=_declare, write=_write, probe=_probe, read_options=("raw",),
    write_options={"sample_type": "float (default), half, uint16 or uint8 (integers sRGB-encoded)",
                   "compression": "zlib (default), lzw, zstd or none",
                   "predictor": "True (default): horizontal or floating-point predictor",
                   "raw": "True: integer codes = value * maxval, no sRGB encoding",
                   "dither": "True: TPDF dither before rounding to integers",
                   "icc": "an ICC profile (bytes) written as tag 34675 (the Display P3 display writes one)",
                   "exif": "camera tags {name: value} (lenslab.io.exif): Make, Model, Orientation and an Exif IFD",
                   "in_place": "True: half floats or integer codes are made in the image's own memory (the array is "
                               "overwritten; the caller gives it up)"},
    compressions=("zlib", "deflate", "lzw", "zstd", "none"),
    note="float samples are linear, 8/16-bit samples sRGB-encoded; the first image of a multi-page file",
    straight_alpha=("uint",)),)
