"""The gain map's metadata, from the ``hdrgm`` XMP namespace (``http://ns.adobe.com/hdr-gain-map/1.0/``) that
Adobe's gain map specification defines and Google's Ultra HDR v1 uses (Ultra HDR, "Gain map metadata" and
its XMP table; Adobe, "Gain Map Metadata").

Each value is one real, or an ``rdf:Seq`` of three (red, green, blue). ``GainMapMin``, ``GainMapMax``,
``HDRCapacityMin`` and ``HDRCapacityMax`` are log2 values (stops). Defaults where a field is absent:
``GainMapMin`` 0, ``Gamma`` 1, ``OffsetSDR`` and ``OffsetHDR`` 1/64, ``HDRCapacityMin`` 0,
``BaseRenditionIsHDR`` False; ``GainMapMax`` and ``HDRCapacityMax`` are required, and ``Version`` must be
``1.0``. A value that is not finite, a ``Gamma`` <= 0, ``GainMapMax`` < ``GainMapMin``, ``HDRCapacityMax``
< ``HDRCapacityMin``, a boost beyond :data:`MAX_STOPS` or an offset beyond +-1 (SDR white; the
specifications' default is 1/64) is refused (:class:`MetadataError`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

HDRGM = "http://ns.adobe.com/hdr-gain-map/1.0/"
RDF = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"
#: the largest |log2 boost| read: 2^64 (beyond any photograph's range, far within float32's 2^128)
MAX_STOPS = 64.0
_DEFAULTS = {"GainMapMin": 0.0, "Gamma": 1.0, "OffsetSDR": 1 / 64, "OffsetHDR": 1 / 64, "HDRCapacityMin": 0.0}
_REQUIRED = ("GainMapMax", "HDRCapacityMax")
_PER_CHANNEL = ("GainMapMin", "GainMapMax", "Gamma", "OffsetSDR", "OffsetHDR")


class MetadataError(ValueError):
    """The gain map metadata is absent, damaged or absurd: what is wrong, in words."""


@dataclass(frozen=True)
class GainMapMetadata:
    """Per-channel ``(r, g, b)`` tuples for the map's values; capacities and the base's kind as scalars."""

    gain_map_min: tuple[float, float, float]
    gain_map_max: tuple[float, float, float]
    gamma: tuple[float, float, float]
    offset_sdr: tuple[float, float, float]
    offset_hdr: tuple[float, float, float]
    hdr_capacity_min: float
    hdr_capacity_max: float
    base_is_hdr: bool = False
    #: whether the gain applies in the base image's colour space (the ``hdrgm`` XMP's only choice) or in the
    #: alternate image's (ISO 21496-1 may say so: the gain map image's ICC profile names it)
    base_colour_space: bool = True

    @property
    def headroom_stops(self) -> float:
        """The headroom of the rendition read, in stops: HDRCapacityMax (log2 of the display boost at
        which the map applies in full)."""
        return self.hdr_capacity_max

    def describe(self) -> str:
        def v(t):
            return f"{t[0]:.4g}" if t[0] == t[1] == t[2] else "(" + ", ".join(f"{x:.4g}" for x in t) + ")"

        return (f"GainMapMin {v(self.gain_map_min)}, GainMapMax {v(self.gain_map_max)} (log2), Gamma {v(self.gamma)}, "
                f"OffsetSDR {v(self.offset_sdr)}, OffsetHDR {v(self.offset_hdr)}, HDRCapacityMin "
                f"{self.hdr_capacity_min:.4g}, HDRCapacityMax {self.hdr_capacity_max:.4g}: headroom "
                f"{self.headroom_stops:.3g} stops ({2.0 ** self.headroom_stops:.3g}x SDR white)"
                + (", base rendition is HDR" if self.base_is_hdr else "")
                + ("" if self.base_colour_space else ", applied in the alternate image's colour space"))


def has_hdrgm(packet: bytes | None) -> bool:
    return packet is not None and HDRGM.encode() in packet


def _fields(packet: bytes) -> dict[str, list[str]]:
    """Every ``hdrgm`` property of the packet's ``rdf:Description`` elements: its text values."""
    from defusedxml import ElementTree

    text = packet.strip(b"\x00 \t\r\n")
    try:
        root = ElementTree.fromstring(text)
    except Exception as exc:  # defusedxml's refusals and ParseError alike: the XMP is damaged
        raise MetadataError(f"its XMP cannot be parsed ({type(exc).__name__})") from None
    out: dict[str, list[str]] = {}
    for desc in root.iter(f"{{{RDF}}}Description"):
        for key, value in desc.attrib.items():
            if key.startswith(f"{{{HDRGM}}}"):
                out[key[len(HDRGM) + 2:]] = [value]
        for child in desc:
            if child.tag.startswith(f"{{{HDRGM}}}"):
                items = [li.text or "" for li in child.iter(f"{{{RDF}}}li")]
                out[child.tag[len(HDRGM) + 2:]] = items or [child.text or ""]
    return out


def _number(name: str, values: list[str], per_channel: bool) -> tuple[float, ...]:
    if len(values) not in ((1, 3) if per_channel else (1,)):
        raise MetadataError(f"its {name} has {len(values)} values")
    try:
        out = tuple(float(v) for v in values)
    except ValueError:
        raise MetadataError(f"its {name} is not a number: {values[0][:40]!r}") from None
    if not all(math.isfinite(x) for x in out):
        raise MetadataError(f"its {name} is not finite ({', '.join(values)})")
    return out * 3 if len(out) == 1 and per_channel else out


def parse(packet: bytes) -> GainMapMetadata:
    """The metadata of an XMP packet holding ``hdrgm`` properties; :class:`MetadataError` when they are
    absent, damaged or absurd (see the module docstring)."""
    fields = _fields(packet)
    version = (fields.get("Version") or [""])[0]
    if version != "1.0":
        raise MetadataError(f"its metadata has version {version[:20]!r}; lenslab reads version 1.0")
    missing = [k for k in _REQUIRED if k not in fields]
    if missing:
        raise MetadataError(f"its metadata lacks {' and '.join(missing)}")
    got = {}
    for name in (*_PER_CHANNEL, "HDRCapacityMin", "HDRCapacityMax"):
        per = name in _PER_CHANNEL
        got[name] = _number(name, fields[name], per) if name in fields else \
            ((_DEFAULTS[name],) * 3 if per else (_DEFAULTS[name],))
    base_hdr = (fields.get("BaseRenditionIsHDR") or ["False"])[0].strip().lower()
    if base_hdr not in ("true", "false"):
        raise MetadataError(f"its BaseRenditionIsHDR is {base_hdr[:20]!r}, not True or False")
    meta = GainMapMetadata(got["GainMapMin"], got["GainMapMax"], got["Gamma"], got["OffsetSDR"], got["OffsetHDR"],
                           got["HDRCapacityMin"][0], got["HDRCapacityMax"][0], base_hdr == "true")
    check(meta)
    return meta


def check(meta: GainMapMetadata) -> None:
    """Refuse metadata no gain map can mean (:class:`MetadataError`)."""
    for lo, hi in zip(meta.gain_map_min, meta.gain_map_max):
        if hi < lo:
            raise MetadataError(f"its GainMapMax {hi:g} is below its GainMapMin {lo:g}")
        if max(abs(lo), abs(hi)) > MAX_STOPS:
            raise MetadataError(f"it boosts by 2^{max(abs(lo), abs(hi)):g}, beyond 2^{MAX_STOPS:g}")
    if min(meta.gamma) <= 0:
        raise MetadataError(f"its Gamma is {min(meta.gamma):g}; it must be above 0")
    if meta.hdr_capacity_max < meta.hdr_capacity_min or meta.hdr_capacity_min < 0 or \
            meta.hdr_capacity_max > MAX_STOPS:
        raise MetadataError(f"its HDRCapacityMin {meta.hdr_capacity_min:g} and HDRCapacityMax "
                            f"{meta.hdr_capacity_max:g} are not 0 <= min <= max <= {MAX_STOPS:g}")
    if max(abs(o) for o in meta.offset_sdr + meta.offset_hdr) > 1.0:
        raise MetadataError("its OffsetSDR or OffsetHDR is beyond +-1 (SDR white)")
