"""HEIF and HEIC (the files phones write): read only, through pillow-heif, the ``lenslab[heif]`` extra (codec:
:mod:`lenslab.io.heif`). Recognised by the brands of its ``ftyp`` box, never by its name."""

from __future__ import annotations

from lenslab.io.plugin import Format, header_only


#: ftyp brands of HEIF still images (image items): HEIF's own and HEVC-coded HEIF's (HEIC)
IMAGE_BRANDS = (b"mif1", b"mif2", b"heic", b"heix", b"heim", b"heis")
#: brands of HEIF image sequences (a track of frames, read as the clip it is: :mod:`lenslab.io.formats.video`)
SEQUENCE_BRANDS = (b"msf1", b"hevc", b"hevx", b"hevm", b"hevs")
#: brands of AV1-coded HEIF (AVIF), which the pillow-heif wheel does not decode
AVIF_BRANDS = (b"avif", b"avis")


def is_heif(head: bytes) -> bool:
    """True if ``head`` (a file's first bytes) starts an ISO base media file whose ``ftyp`` box names a HEIF
    brand as its major brand and a still image among its brands: an HEVC image brand (``heic``...), or another
    HEIF brand (``mif1``; a sequence brand, ``msf1`` or ``hevc``, beside an image brand in ``head``) without an
    AVIF brand. A sequence brand alone is an image sequence, which holds no still image: a clip.

    >>> is_heif(b"\\x00\\x00\\x00\\x18ftypheic\\x00\\x00\\x00\\x00mif1heic"), is_heif(b"\\x00\\x00\\x00\\x18ftypisom")
    (True, False)
    >>> is_heif(b"\\x00\\x00\\x00\\x1cftypmif1\\x00\\x00\\x00\\x00mif1avifmiaf")  # AVIF
    False
    >>> is_heif(b"\\x00\\x00\\x00\\x18ftypmsf1\\x00\\x00\\x00\\x00msf1hevc")  # an image sequence
    False
    """
    if len(head) < 12 or head[4:8] != b"ftyp":
        return False
    major = head[8:12]
    size = int.from_bytes(head[:4], "big")
    brands = [major] + [head[i:i + 4] for i in range(16, min(size, len(head)) - 3, 4)]
    if not any(b in IMAGE_BRANDS for b in brands):  # no still image: not HEIF, or an image sequence
        return False
    return major in IMAGE_BRANDS[2:] or (major in IMAGE_BRANDS + SEQUENCE_BRANDS
                                          and not any(b in AVIF_BRANDS for b in brands))


def _read(path, selector=None, raw=False, parsed=None):
    from lenslab.io.heif import read_heif

    return read_heif(path, selector, raw=raw, parsed=parsed)


def _declare(path, **options):
    from lenslab.io.heif import declare

    return declare(path, **options)


FORMATS = (Format(
    name="heif", title="HEIF/HEIC", extensions=(".heic", ".heif", ".hif"), magic=is_heif,
    hdr=False, alpha=True, channels=(1, 2, 3, 4), bit_depths=(8, 10, 12), sample_types=("uint",), read=_read,
    declare=_declare, probe=header_only, read_options=("raw",), selectors=True, straight_alpha=("uint",),
    note="read only (pillow-heif: lenslab[heif]); the primary image, others as FILE:INDEX; ICC, nclx sRGB, PQ and "
         "HLG decoded; depth images and gain maps ignored"),)
