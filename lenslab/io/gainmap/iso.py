"""The gain map's metadata from its ISO 21496-1 binary block: the ``APP2`` segment that starts
``urn:iso:std:iso:ts:21496:-1\\0``, laid out as Google's libultrahdr writes and reads it
(``lib/src/gainmapmetadata.cpp``, ``uhdr_gainmap_metadata_frac::decodeGainmapMetadata``; the segments'
places in ``lib/src/jpegr.cpp``, ``JpegR::appendGainMap``).

- The **primary image** holds a version block only: ``minimum_version`` and ``writer_version``, two big-endian
  ``u16``. A reader of version 0 reads a file whose ``minimum_version`` is 0.
- The **gain map image** holds the metadata, every integer big-endian:

  ======================  =====================================================================================
  ``u16`` ``u16``         ``minimum_version`` (0), ``writer_version``
  ``u8`` flags            0x80: three channels of values follow (else one, for all three); 0x40: the gain
                          applies in the base image's colour space (else in the alternate image's: the gain
                          map image's ICC profile); 0x04: the base is the HDR rendition (backward direction);
                          0x08: one common denominator
  common denominator      ``u32`` D, ``u32`` base HDR headroom N, ``u32`` alternate HDR headroom N, then per
                          channel ``s32`` gain map min N, ``s32`` max N, ``u32`` gamma N, ``s32`` base offset
                          N, ``s32`` alternate offset N
  otherwise               ``u32`` N and ``u32`` D of the base headroom, then of the alternate headroom; per
                          channel N and D of the min (``s32``, ``u32``), max (``s32``, ``u32``), gamma (``u32``,
                          ``u32``), base offset (``s32``, ``u32``), alternate offset (``s32``, ``u32``)
  ======================  =====================================================================================

This is the layout of libultrahdr 1.3 and later; earlier drafts (a one-byte version, flags 0x01 and 0x02, as in
early libavif and libheif ``tmap`` boxes) mostly read as a minimum version other than 0 and are refused, as
libultrahdr 1.4 refuses them. Each value is N / D. They mean what the ``hdrgm`` XMP's do (libultrahdr's
``gainmapMetadataFractionToFloat``): gain map min and max are ``GainMapMin`` and ``GainMapMax`` (log2), the
gamma ``Gamma``, the base and alternate offsets ``OffsetSDR`` and ``OffsetHDR``, the base and alternate HDR
headrooms ``HDRCapacityMin`` and ``HDRCapacityMax`` (log2), the lower and the higher of the two in the backward
direction (0x04: the base is HDR, its headroom the higher; ``BaseRenditionIsHDR``, whose map lenslab does not
apply). Bytes after the last value are ignored, as libultrahdr ignores them (a later writer version may append
fields). A block cut short, of another minimum version, with a denominator of 0 or with values
:func:`lenslab.io.gainmap.metadata.check` refuses raises :class:`lenslab.io.gainmap.metadata.MetadataError`.
"""

from __future__ import annotations

from lenslab.io.gainmap.metadata import GainMapMetadata, MetadataError, check

MULTI_CHANNEL, BASE_COLOUR_SPACE, BACKWARD, COMMON_DENOMINATOR = 0x80, 0x40, 0x04, 0x08
NAME = "ISO 21496-1"


class _Reader:
    def __init__(self, data: bytes):
        self.data, self.pos = data, 0

    def take(self, size: int, signed: bool = False) -> int:
        if len(self.data) - self.pos < size:
            raise MetadataError(f"its {NAME} metadata is cut short ({len(self.data)} bytes; the fields its flags "
                                f"name need more)")
        value = int.from_bytes(self.data[self.pos:self.pos + size], "big", signed=signed)
        self.pos += size
        return value


def version(payload: bytes) -> tuple[int, int]:
    """``(minimum_version, writer_version)`` of a block (the primary image's, or the start of the gain map's);
    :class:`MetadataError` where it is cut short or asks for a reader newer than version 0."""
    r = _Reader(payload)
    minimum, writer = r.take(2), r.take(2)
    if minimum != 0:
        raise MetadataError(f"its {NAME} metadata needs a reader of version {minimum}; lenslab reads version 0")
    return minimum, writer


def _ratio(n: int, d: int, name: str) -> float:
    if d == 0:
        raise MetadataError(f"its {NAME} {name} has a denominator of 0")
    return n / d


def parse(payload: bytes) -> GainMapMetadata:
    """The metadata of a gain map image's block (after its signature); :class:`MetadataError` where it is
    damaged or absurd."""
    version(payload)
    r = _Reader(payload)
    r.pos = 4
    flags = r.take(1)
    channels = 3 if flags & MULTI_CHANNEL else 1
    fields = ("GainMapMin", True), ("GainMapMax", True), ("Gamma", False), ("OffsetSDR", True), ("OffsetHDR", True)
    if flags & COMMON_DENOMINATOR:
        d = r.take(4)
        base, alternate = _ratio(r.take(4), d, "HDRCapacityMin"), _ratio(r.take(4), d, "HDRCapacityMax")
        values = [[_ratio(r.take(4, signed), d, name) for name, signed in fields] for _ in range(channels)]
    else:
        base = _ratio(r.take(4), r.take(4), "HDRCapacityMin")
        alternate = _ratio(r.take(4), r.take(4), "HDRCapacityMax")
        values = [[_ratio(r.take(4, signed), r.take(4), name) for name, signed in fields] for _ in range(channels)]
    per = tuple(tuple(values[c if channels == 3 else 0][k] for c in range(3)) for k in range(len(fields)))
    if flags & BACKWARD:  # the base is the HDR rendition: its headroom is the higher one, the map's range below it
        base, alternate = sorted((base, alternate))
    meta = GainMapMetadata(*per, hdr_capacity_min=base, hdr_capacity_max=alternate,
                           base_is_hdr=bool(flags & BACKWARD), base_colour_space=bool(flags & BASE_COLOUR_SPACE))
    check(meta)
    return meta


def differences(xmp: GainMapMetadata, iso: GainMapMetadata) -> list[str]:
    """Where the ``hdrgm`` XMP and the ISO block disagree: ``"NAME xmp against iso"`` for each field. XMP writers
    print 6 decimals and the block holds 32-bit rationals: values within 1e-5 (absolute, or relative to the
    value) agree."""
    import math

    out = []
    names = ("GainMapMin", "GainMapMax", "Gamma", "OffsetSDR", "OffsetHDR", "HDRCapacityMin", "HDRCapacityMax",
             "BaseRenditionIsHDR")
    keys = ("gain_map_min", "gain_map_max", "gamma", "offset_sdr", "offset_hdr", "hdr_capacity_min",
            "hdr_capacity_max", "base_is_hdr")
    for name, key in zip(names, keys):
        a, b = getattr(xmp, key), getattr(iso, key)
        ta, tb = (a, b) if isinstance(a, tuple) else ((a,), (b,))
        if not all(math.isclose(x, y, rel_tol=1e-5, abs_tol=1e-5) for x, y in zip(ta, tb)):
            def words(t):
                return f"{t[0]:.6g}" if len(set(t)) == 1 else "(" + ", ".join(f"{x:.6g}" for x in t) + ")"

            out.append(f"{name} {words(ta)} against {words(tb)}")
    return out
