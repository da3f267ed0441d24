"""Ultra HDR JPEGs written here from the specifications, independently of lenslab's reader: Google's Ultra HDR
v1.0 ("Gain map container": primary image with XMP ``hdrgm:Version`` and a GContainer directory and an MPF
``APP2`` segment; the gain map JPEG after it, its own XMP holding the ``hdrgm`` metadata) and CIPA DC-007 (the MP
Index IFD: version, number of images, one 16-byte MP entry per image, offsets from the MPF TIFF header, the
first image's 0). Images are encoded with Pillow."""

from __future__ import annotations

import io
import struct

import numpy as np
from PIL import Image

XMP_SIG = b"http://ns.adobe.com/xap/1.0/\x00"


def jpeg(codes: np.ndarray, quality: int = 100, subsampling: int = 0) -> bytes:
    """8-bit codes (H x W or H x W x 3) as a baseline JPEG, 4:4:4 (Pillow's ``subsampling`` 0; 2 is 4:2:0)."""
    a = np.asarray(codes, np.uint8)
    im = Image.fromarray(a[..., 0] if a.ndim == 3 and a.shape[2] == 1 else a)
    buf = io.BytesIO()
    im.save(buf, "JPEG", quality=quality, subsampling=subsampling)
    return buf.getvalue()


def _segment(marker: int, payload: bytes) -> bytes:
    return bytes([0xFF, marker]) + struct.pack(">H", len(payload) + 2) + payload


def _after_soi(jpg: bytes, *segments: bytes) -> bytes:
    assert jpg[:2] == b"\xff\xd8"
    return jpg[:2] + b"".join(segments) + jpg[2:]


def _seq(v) -> str:
    return str(v) if np.isscalar(v) or isinstance(v, str) else None


def gain_map_xmp(**fields) -> bytes:
    """An XMP packet with ``hdrgm:NAME`` properties: scalars as attributes, triples as ``rdf:Seq``."""
    attrs = " ".join(f'hdrgm:{k}="{v}"' for k, v in fields.items() if _seq(v) is not None)
    seqs = "".join(f"<hdrgm:{k}><rdf:Seq>" + "".join(f"<rdf:li>{x}</rdf:li>" for x in v) + f"</rdf:Seq></hdrgm:{k}>"
                   for k, v in fields.items() if _seq(v) is None)
    return ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
            '<rdf:Description rdf:about="" xmlns:hdrgm="http://ns.adobe.com/hdr-gain-map/1.0/" '
            f'{attrs}>{seqs}</rdf:Description></rdf:RDF></x:xmpmeta>').encode()


def primary_xmp(gain_length: int) -> bytes:
    return ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
            '<rdf:Description rdf:about="" xmlns:hdrgm="http://ns.adobe.com/hdr-gain-map/1.0/" '
            'xmlns:Container="http://ns.google.com/photos/1.0/container/" '
            'xmlns:Item="http://ns.google.com/photos/1.0/container/item/" hdrgm:Version="1.0">'
            '<Container:Directory><rdf:Seq>'
            '<rdf:li rdf:parseType="Resource"><Container:Item Item:Semantic="Primary" Item:Mime="image/jpeg"/></rdf:li>'
            f'<rdf:li rdf:parseType="Resource"><Container:Item Item:Semantic="GainMap" Item:Mime="image/jpeg" '
            f'Item:Length="{gain_length}"/></rdf:li></rdf:Seq></Container:Directory>'
            '</rdf:Description></rdf:RDF></x:xmpmeta>').encode()


def _mpf(primary_size: int, gain_size: int, gain_offset: int) -> bytes:
    """The MPF APP2 payload (after ``MPF\\0``): little-endian TIFF header, MP Index IFD, two MP entries."""
    entries_at = 8 + 2 + 3 * 12 + 4
    ifd = struct.pack("<H", 3)
    ifd += struct.pack("<HHI4s", 0xB000, 7, 4, b"0100")
    ifd += struct.pack("<HHII", 0xB001, 4, 1, 2)
    ifd += struct.pack("<HHII", 0xB002, 7, 32, entries_at)
    ifd += struct.pack("<I", 0)
    entries = struct.pack("<IIIHH", 0x030000, primary_size, 0, 0, 0) + struct.pack("<IIIHH", 0, gain_size,
                                                                                    gain_offset, 0, 0)
    return b"II*\x00" + struct.pack("<I", 8) + ifd + entries


def iso_21496(gmin, gmax, gamma, off_sdr, off_hdr, cap_min: float, cap_max: float, flags: int = 0x40,
              denominator: int = 1 << 20) -> bytes:
    """An ISO 21496-1 gain map block (after its signature), laid out as libultrahdr's
    ``uhdr_gainmap_metadata_frac::encodeGainmapMetadata`` writes it: ``u16`` minimum and writer versions (0), the
    flags byte (0x80 three channels, 0x40 the base's colour space, 0x04 HDR base, 0x08 a common denominator), then
    the rationals, big-endian; each value ``v`` as ``round(v * denominator) / denominator``. Per-channel values
    are written three times where ``flags`` has 0x80, once (the first) otherwise."""
    channels = 3 if flags & 0x80 else 1
    per = [np.broadcast_to(np.asarray(v, np.float64), (3,)) for v in (gmin, gmax, gamma, off_sdr, off_hdr)]

    def n(v) -> int:
        return int(round(float(v) * denominator))

    out = struct.pack(">HHB", 0, 0, flags)
    if flags & 0x08:
        out += struct.pack(">III", denominator, n(cap_min), n(cap_max))
        for c in range(channels):
            out += struct.pack(">iiIii", *(n(v[c]) for v in per))
    else:
        out += struct.pack(">IIII", n(cap_min), denominator, n(cap_max), denominator)
        for c in range(channels):
            out += struct.pack(">iIiIIIiIiI", *(x for v in per for x in (n(v[c]), denominator)))
    return out


def ultrahdr(base_jpeg: bytes, gain_jpeg: bytes, metadata: dict | None, offset_shift: int = 0,
             iso: bytes | None = None, iso_version: bytes | None = None) -> bytes:
    """The Ultra HDR file: ``base_jpeg`` with its XMP and MPF index, then ``gain_jpeg`` with ``metadata``
    (``hdrgm`` fields; None: no XMP) in its XMP. ``offset_shift`` is added to the gain map's MPF offset (a damaged
    index); ``iso``: the payload of an ISO 21496-1 ``APP2`` segment given to the gain map; ``iso_version``: that
    of the primary image's version block (libultrahdr writes ``00 00 00 00``)."""
    segments = [] if metadata is None else [_segment(0xE1, XMP_SIG + gain_map_xmp(**{"Version": "1.0", **metadata}))]
    if iso is not None:
        segments.append(_segment(0xE2, b"urn:iso:std:iso:ts:21496:-1\x00" + iso))
    gain = _after_soi(gain_jpeg, *segments)
    xmp_segment = _segment(0xE1, XMP_SIG + primary_xmp(len(gain)))
    if iso_version is not None:
        xmp_segment += _segment(0xE2, b"urn:iso:std:iso:ts:21496:-1\x00" + iso_version)
    mpf_len = len(_segment(0xE2, b"MPF\x00" + _mpf(0, 0, 0)))
    primary_size = len(base_jpeg) + len(xmp_segment) + mpf_len
    tiff_at = 2 + len(xmp_segment) + 4 + 4  # SOI, the XMP segment, the APP2 marker and length, "MPF\0"
    mpf = _segment(0xE2, b"MPF\x00" + _mpf(primary_size, len(gain), primary_size - tiff_at + offset_shift))
    return _after_soi(base_jpeg, xmp_segment, mpf) + gain


def srgb_decode(v):
    """IEC 61966-2-1 sRGB EOTF, float64."""
    v = np.asarray(v, np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def srgb_encode(v):
    v = np.asarray(v, np.float64)
    return np.where(v <= 0.0031308, v * 12.92, 1.055 * np.maximum(v, 0) ** (1 / 2.4) - 0.055)


def bilinear_at_centres(g: np.ndarray, height: int, width: int, step: int = 1) -> np.ndarray:
    """``g`` (h x w x c, float64) sampled at the centres of an ``height x width`` grid covering the same extent
    (every ``step``-th row and column), written as the textbook two-tap interpolation per axis, edges clamped
    (pixel centres at +0.5)."""
    h, w = g.shape[:2]

    def axis(n_out, n_in):
        u = np.clip((np.arange(0, n_out, step) + 0.5) * n_in / n_out - 0.5, 0, n_in - 1)
        i0 = np.floor(u).astype(int)
        i1 = np.minimum(i0 + 1, n_in - 1)
        return i0, i1, u - i0

    y0, y1, fy = axis(height, h)
    x0, x1, fx = axis(width, w)
    rows = g[y0] * (1 - fy)[:, None, None] + g[y1] * fy[:, None, None]
    return rows[:, x0] * (1 - fx)[None, :, None] + rows[:, x1] * fx[None, :, None]


def apply_formula(sdr, recovery, gmin, gmax, gamma, off_sdr, off_hdr):
    """Ultra HDR v1 / Adobe: HDR = (SDR + k_sdr) * 2^(min + (max - min) * r^(1/gamma)) - k_hdr, weight 1, float64."""
    gmin, gmax, gamma, off_sdr, off_hdr = (np.broadcast_to(np.asarray(v, np.float64), (3,))
                                           for v in (gmin, gmax, gamma, off_sdr, off_hdr))
    log_boost = gmin * (1 - recovery ** (1 / gamma)) + gmax * recovery ** (1 / gamma)
    return (sdr + off_sdr) * np.exp2(log_boost) - off_hdr
