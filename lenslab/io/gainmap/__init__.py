"""Ultra HDR JPEGs: an SDR base image, and a gain map that turns it into the HDR photo it was taken as.

Sections followed: Google's Ultra HDR Image Format v1.0 (developer.android.com/media/platform/hdr-image-format):
"Gain map container" (the MPF index of the secondary image, the ``hdrgm`` XMP of the gain map image),
"Gain map metadata", "Decode" (gain map sampling and application, weight factor); Adobe's Gain Map
Specification 1.0: "Gain Map Metadata", "Applying the Gain Map" (per-channel values, ``BaseRenditionIsHDR``).

- **Found** through the primary image's MPF index (:func:`lenslab.io.gainmap.container.mpf_images`): the first
  secondary JPEG that holds an ISO 21496-1 block or ``hdrgm`` XMP values (the primary's XMP, where the gain map's
  has none).
- **Metadata**: the ISO 21496-1 block of the gain map image (:mod:`lenslab.io.gainmap.iso`) where it has one,
  else the ``hdrgm`` XMP (:mod:`lenslab.io.gainmap.metadata`). The ISO block wins, as in libultrahdr's decoder
  (``lib/src/jpegr.cpp``, ``JpegR::parseGainMapMetadata``: the ISO block when there is one, the XMP otherwise),
  so a damaged ISO block leaves the base image even beside a good XMP; where both are read and disagree, the
  difference is named. The primary image's ISO version block, where present, must allow a reader of version 0.
- **Applied** at full headroom: :mod:`lenslab.io.gainmap.apply`; in the gain map image's ICC colour space where
  the ISO block says the gain applies in the alternate image's colour space and differs by channel.
- **Not read**: gain maps found by the GContainer item lengths alone (no MPF index); extended XMP. A base
  rendition that is itself HDR (``BaseRenditionIsHDR``, the ISO block's backward direction) is read as it is,
  with a note (its gain map maps it down to SDR).
- **Refused** (the base image is read, with a note that says why): an MPF index pointing outside the file, a
  gain map cut short or that OpenCV cannot decode, larger than the base in either direction, of other than 1 or
  3 channels, with absurd or damaged metadata (:class:`lenslab.io.gainmap.metadata.MetadataError`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.io.gainmap import iso as iso_block
from lenslab.io.gainmap.container import ISO_SIGNATURE, ContainerError, frame, mpf_images, payloads, xmp
from lenslab.io.gainmap.metadata import GainMapMetadata, MetadataError, has_hdrgm, parse

#: the selector that reads the SDR base image (``photo.jpg:sdr``), and the one naming the default
SDR, HDR = "sdr", "hdr"


class Skipped(ValueError):
    """A gain map that is not applied: why, in words (the base image is read). ``hdr_base``: the base image is
    the HDR rendition already (``BaseRenditionIsHDR``)."""

    def __init__(self, why: str, hdr_base: bool = False):
        super().__init__(why)
        self.hdr_base = hdr_base


@dataclass
class GainMap:
    """A gain map ready to apply: its samples (``h x w x c`` uint8) and metadata; ``source``: where the
    metadata was read, in words ("" for the ``hdrgm`` XMP); ``space``: the name of the alternate image's colour
    space and its 3 x 3 matrix to Rec.709 (None: Rec.709 itself), from the gain map image's ICC profile, where
    the gain differs by channel and applies in that space (None otherwise: the base's)."""

    codes: np.ndarray
    meta: GainMapMetadata
    source: str = ""
    space: tuple[str, np.ndarray | None] | None = None

    def describe(self) -> str:
        h, w, c = self.codes.shape
        meta = self.meta.describe() + (f" (ICC profile '{self.space[0]}')" if self.space else "")
        return f"{w} x {h}, {c} channel(s); {meta}" + (f"; {self.source}" if self.source else "")


def present(data: bytes) -> bool:
    """Whether the file names a gain map at all (Ultra HDR / Adobe ``hdrgm`` XMP, or ISO 21496-1)."""
    return b"hdrgm:" in data or ISO_SIGNATURE[:-1] in data


def _iso_source(meta: GainMapMetadata, packet: bytes | None) -> str:
    """How ``info`` names metadata read from the ISO 21496-1 block beside the ``hdrgm`` XMP ``packet``."""
    used = f"metadata from its {iso_block.NAME} block"
    if packet is None:
        return used
    try:
        other = parse(packet)
    except MetadataError as exc:
        return f"{used} (libultrahdr's choice); its hdrgm XMP is not used ({exc})"
    differ = iso_block.differences(other, meta)
    if not differ:
        return f"{used}; its hdrgm XMP agrees"
    return f"{used} (libultrahdr's choice); its hdrgm XMP disagrees: " + ", ".join(
        d.replace(" against ", " in the XMP against ") for d in differ)


def _secondary(data: bytes, images) -> tuple[int, int, GainMapMetadata, str]:
    """The gain map image's (offset, size, metadata, where the metadata was read in words: "" for the XMP)."""
    primary = xmp(data)
    for block in payloads(data, 0xE2, ISO_SIGNATURE)[:1]:
        iso_block.version(block)
    missing = ""
    for k, (at, size) in enumerate(images[1:], 2):
        if data[at:at + 2] != b"\xff\xd8":
            missing = f"its MPF index puts picture {k} at byte {at}, where no JPEG image starts"
            continue
        own = xmp(data, at)
        packet = own if has_hdrgm(own) else primary if has_hdrgm(primary) and b"GainMapMax" in primary else None
        blocks = [b for b in payloads(data, 0xE2, ISO_SIGNATURE, at) if b]  # libultrahdr: the first not empty
        if blocks:
            meta = iso_block.parse(blocks[0])
            return at, size, meta, _iso_source(meta, packet)
        if packet is not None:
            return at, size, parse(packet), ""
    raise Skipped(missing or "no secondary image of its MPF index carries hdrgm or ISO 21496-1 metadata")


def declared(data: bytes, total: int, read_at) -> tuple[int, int, int] | None:
    """``(w, h, c)`` of the gain map the MPF index of a JPEG's head ``data`` (of a file of ``total`` bytes)
    points to, reading the gain map's head by ``read_at(offset, size)``; None where there is none to decode."""
    try:
        images = mpf_images(data, total)
    except ContainerError:
        return None
    if not images or len(images) < 2 or not present(data):
        return None
    found = []
    for at, size in images[1:]:
        head = read_at(at, min(size, 1 << 16))
        try:
            f = frame(head)
        except ContainerError:
            f = None
        if f is not None:
            found.append((f[0], f[1], 3 if f[2] >= 3 else 1))
    return max(found, key=lambda s: s[0] * s[1] * s[2]) if found else None


def prepare(data: bytes, base: tuple[int, int, int]) -> GainMap:
    """The gain map of a JPEG file's bytes whose base image is ``base`` = (W, H, channels), decoded and
    checked; :class:`Skipped` with the reason where it cannot be applied."""
    import cv2

    try:
        images = mpf_images(data)
        if not images or len(images) < 2:
            raise Skipped("the file has no MPF index of a second image to hold it")
        at, size, meta, source = _secondary(data, images)
    except (ContainerError, MetadataError) as exc:
        raise Skipped(str(exc)) from None
    if meta.base_is_hdr:
        raise Skipped("its base image is the HDR rendition (BaseRenditionIsHDR): read as it is; the map to SDR is "
                      "not applied", hdr_base=True)
    blob = data[at:at + size]
    try:
        f = frame(blob)
    except ContainerError as exc:
        raise Skipped(f"its image is damaged: {exc}") from None
    if f is None:
        raise Skipped("its image has no frame header and scan; it is damaged")
    w, h, comps, arithmetic, scan = f
    width, height, channels = base
    if not (0 < w <= width and 0 < h <= height) or comps not in (1, 3):
        raise Skipped(f"it declares {w} x {h} pixels of {comps} component(s); it must have 1 or 3 channels and be "
                      f"no larger than the base's {width} x {height}")
    if channels == 1 and (comps == 3 or len({*meta.gain_map_min}) > 1 or len({*meta.gain_map_max}) > 1):
        raise Skipped("its base image is grey and its samples or metadata differ by colour channel")
    blocks = -(-w // 8) * -(-h // 8)
    if blob.rfind(b"\xff\xd9") < scan or (not arithmetic and size - scan < blocks // 8):
        raise Skipped("its image is cut short (truncated)")
    codes = cv2.imdecode(np.frombuffer(blob, np.uint8), cv2.IMREAD_UNCHANGED)
    if codes is None or codes.dtype != np.uint8 or codes.shape[:2] != (h, w):
        raise Skipped("OpenCV cannot decode its image; it is damaged")
    codes = codes[..., None] if codes.ndim == 2 else np.ascontiguousarray(codes[..., 2::-1])
    return GainMap(codes, meta, source, _alternate_space(blob, codes, meta))


def _alternate_space(blob: bytes, codes: np.ndarray, meta: GainMapMetadata):
    """:attr:`GainMap.space` of a gain map image ``blob``: its ICC profile's name and matrix to Rec.709 where
    the gain differs by channel and applies in the alternate image's colour space; None where it applies in the
    base's, or the gain map image has no profile lenslab applies (libultrahdr then takes the base's gamut:
    ``JpegR::applyGainMap``). A damaged profile is :class:`Skipped`."""
    from lenslab.io.gainmap.apply import per_channel

    if meta.base_colour_space or not per_channel(codes, meta):
        return None
    from lenslab.errors import FormatError
    from lenslab.io.colour.icc import check, plan
    from lenslab.io.colour.icc_chunks import jpeg_profile

    where = "its gain map image"
    try:
        profile = jpeg_profile(blob, where)
        if profile is None:
            return None
        check(profile, where)
        how = plan(profile, 3, where)
    except FormatError as exc:
        raise Skipped(str(exc)) from None
    return (how.name, how.matrix if how.kind == "matrix" else None) if how.kind in ("matrix", "srgb") else None


#: how the ``rendition`` attribute of a file read as its HDR rendition begins (``lenslab info`` looks for it)
HDR_RENDITION = "HDR: the SDR base image with its gain map applied"


def rendition_note(gain: GainMap) -> str:
    return (f"{HDR_RENDITION} at full headroom "
            f"({gain.meta.headroom_stops:.3g} stops); 'FILE:sdr' reads the SDR base image")
