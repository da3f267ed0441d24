"""Embedded ICC profiles (ICC.1:2022, v4.4; v2 profiles too): what the PNG, JPEG and TIFF readers do with one.

A matrix/TRC profile (Display P3, Adobe RGB (1998), ProPhoto/ROMM, Rec.2020, their linear variants) is applied
exactly: each channel's code value goes through the profile's tone curve (``rTRC``, ``gTRC``, ``bTRC``:
``curv`` with a gamma or a table, interpolated linearly as ICC.1 10.6 says, or ``para`` of function types 0 to
4, ICC.1 10.18), evaluated in float64 at every code value of the file's depth; then the colorants (``rXYZ``,
``gXYZ``, ``bXYZ``, adapted to the D50 connection space) are taken back to the device's own white through the
inverse of the profile's ``chad`` tag (Bradford from the media white point ``wtpt`` to D50 when it has none,
as v2 profiles do), and the light they describe goes to linear Rec.709 by colour-science's matrix from the
primaries' and white's chromaticities, its white to D65 by Bradford (:func:`lenslab.io.colour.primaries.
matrix_from_chromaticities`): the file's white becomes Rec.709's white, as an ICC reader's relative
colorimetric rendering makes it. A grey profile's ``kTRC`` is applied the same way (no colorants). Float
samples (TIFF) are linear light: only a linear profile's colorants apply to them (:func:`linear`).

A profile whose matrix is the identity within :data:`SRGB_MATRIX_TOLERANCE` and whose curves are sRGB's within
:data:`SRGB_CURVE_TOLERANCE` is sRGB: the file reads exactly as one without a profile. Any other profile
(LUT-based ``A2B0``, CMYK, Lab, a grey profile on RGB samples or the reverse) is not applied: the file reads as
sRGB, as before, and a one-line note says so. A profile that is damaged or hostile (larger than
:data:`MAX_BYTES`, a declared size beyond its bytes, a tag outside the profile, a curve of zero gamma or that
leaves the finite numbers, colorants that do not span a colour space) is refused with a one-line
:class:`~lenslab.errors.FormatError`. littleCMS (through Pillow's ``ImageCms``) parses the profile first and
gives the colorants, ``chad`` and ``wtpt``; only the curves' bytes are read here, bounds checked.
"""

from __future__ import annotations

import io
import struct
from dataclasses import dataclass

import numpy as np

from lenslab.errors import FormatError

#: the largest profile read: display profiles are under 4 kB, print profiles with large tables under 1 MB
MAX_BYTES = 4 << 20
#: the connection space's white, ICC.1 7.2.16 (the header's PCS illuminant)
D50 = (0.9642, 1.0, 0.8249)
#: a profile is sRGB when its matrix to Rec.709 is the identity within this (colorants are s15.16 numbers that
#: makers round and adapt differently: 2e-3 is a 2/1000 change of a primary's light, under half an 8-bit step
#: at white)
SRGB_MATRIX_TOLERANCE = 2e-3
#: ...and its curves are sRGB's within this much linear light at 4097 points (a 1024-entry table is within 8e-6;
#: a gamma of 2.2 is 8.5e-3 away and is not sRGB)
SRGB_CURVE_TOLERANCE = 1e-4
#: ``para`` parameter counts per function type (ICC.1 table 68)
PARA_COUNTS = {0: 1, 1: 3, 2: 4, 3: 5, 4: 7}
LUT_TAGS = (b"A2B0", b"A2B1", b"A2B2", b"D2B0", b"D2B1", b"D2B2")


@dataclass(frozen=True)
class Plan:
    """What a reader does with a profile: ``kind`` "srgb" (read as sRGB), "matrix" (``curves`` per colour
    channel, then ``matrix``, 3 x 3 file RGB -> Rec.709), "grey" (one curve) or "ignored" (read as sRGB);
    ``note`` is the one line ``lenslab info`` shows; ``name`` the profile's description."""

    kind: str
    note: str
    curves: tuple = ()
    matrix: np.ndarray | None = None
    name: str = ""


def refuse(where: str, what: str):
    raise FormatError(f"{where}: the embedded ICC profile {what}; remove it or save the image without one")


def check(data: bytes, where: str) -> None:
    """Refuses a damaged profile (its header, size, tag table) in one line, before any pixel is decoded."""
    _tags(data, where)


def _tags(data: bytes, where: str) -> dict[bytes, tuple[int, int]]:
    """The tag table (signature -> offset, size), every tag inside the profile's declared size."""
    if len(data) > MAX_BYTES:
        refuse(where, f"is {len(data)} bytes, more than the {MAX_BYTES >> 20} MiB a profile is read up to")
    if len(data) < 132 or data[36:40] != b"acsp":
        refuse(where, "is damaged (no ICC header)")
    size, count = struct.unpack(">I", data[:4])[0], struct.unpack(">I", data[128:132])[0]
    if size > len(data) or size < 132:
        refuse(where, f"declares {size} bytes and holds {len(data)}")
    if count > (size - 132) // 12:
        refuse(where, f"declares {count} tags, more than its {size} bytes hold")
    tags = {}
    for i in range(count):
        sig, offset, length = struct.unpack(">4sII", data[132 + 12 * i:144 + 12 * i])
        if offset + length > size or length < 8:
            refuse(where, f"has a tag {sig!r} outside its {size} bytes")
        tags.setdefault(sig, (offset, length))
    return tags


def curve(data: bytes, tag: tuple[int, int], where: str):
    """The tone curve of a ``curv`` or ``para`` tag: float64 code values in [0, 1] -> linear light in [0, 1]
    (clipped there, as littleCMS clips a curve's output)."""
    offset, length = tag
    body = data[offset:offset + length]
    kind = body[:4]
    if kind == b"curv" and length >= 12:
        n = struct.unpack(">I", body[8:12])[0]
        if 12 + 2 * n > length:
            refuse(where, f"has a curve of {n} entries in a tag of {length} bytes")
        if n == 0:
            return lambda x: x
        if n == 1:
            gamma = struct.unpack(">H", body[12:14])[0] / 256.0
            if gamma <= 0:
                refuse(where, "has a curve of gamma 0")
            return lambda x: x ** gamma
        table = np.frombuffer(body, ">u2", n, 12).astype(np.float64) / 65535.0
        return lambda x: np.interp(x * (n - 1), np.arange(n, dtype=np.float64), table)
    if kind == b"para" and length >= 12:
        function = struct.unpack(">H", body[8:10])[0]
        count = PARA_COUNTS.get(function)
        if count is None or 12 + 4 * count > length:
            refuse(where, f"has a parametric curve of type {function} that is unknown or cut short")
        p = [v / 65536.0 for v in struct.unpack(f">{count}i", body[12:12 + 4 * count])] + [0.0] * (7 - count)
        g, a, b, c, d, e, f = p
        if g <= 0 or (function in (1, 2) and a == 0):
            refuse(where, f"has a parametric curve of gamma {g:g} and slope {a:g}")
        if function in (1, 2):  # zero (type 2: c) below -b / a
            offset = c if function == 2 else 0.0
            d, c, e, f = -b / a, 0.0, offset, offset
        power = lambda x: np.clip(a * x + b, 0.0, None) ** g  # noqa: E731
        if function == 0:
            return lambda x: x ** g
        return lambda x: np.where(x >= d, power(x) + e, c * x + f)
    refuse(where, f"has a tone curve of type {kind!r}, not curv or para")


def evaluate(fn, maxval: int, where: str) -> np.ndarray:
    """float32 table of ``fn`` at every code value 0..maxval; refused when it leaves the finite numbers."""
    with np.errstate(all="ignore"):
        y = np.asarray(fn(np.arange(maxval + 1, dtype=np.float64) / maxval), dtype=np.float64)
    if not np.all(np.isfinite(y)):
        refuse(where, "has a tone curve whose values are not finite")
    return np.clip(y, 0.0, 1.0).astype(np.float32)


def _xyz(value) -> np.ndarray | None:
    return None if value is None else np.asarray(value[0], dtype=np.float64)


def _to_rec709(pcs: np.ndarray, chad: np.ndarray, where: str) -> np.ndarray:
    """3 x 3 device RGB -> linear Rec.709 from the colorants (columns, D50 PCS) and the adaptation to D50."""
    from lenslab.io.colour.primaries import matrix_from_chromaticities

    if not (np.all(np.isfinite(pcs)) and np.all(np.isfinite(chad))) or abs(np.linalg.det(chad)) < 1e-6:
        refuse(where, "has colorants or a chromatic adaptation that are not numbers a profile holds")
    native = np.linalg.solve(chad, pcs)  # the colorants under the device's own white
    columns = np.concatenate([native, native.sum(axis=1, keepdims=True)], axis=1)
    sums = columns.sum(axis=0)
    if np.any(sums <= 1e-6) or abs(np.linalg.det(native)) < 1e-9:
        refuse(where, "has colorants that do not span a colour space")
    xy = (columns[:2] / sums).T.reshape(-1)
    m = matrix_from_chromaticities(xy, adaptation="Bradford")
    if not np.all(np.isfinite(m)):
        refuse(where, "has colorants that do not span a colour space")
    return m


def _bradford_to_d50(white) -> np.ndarray:
    from lenslab.srgb import colour_science

    colour = colour_science()

    if white is None:
        return np.eye(3)
    return colour.adaptation.matrix_chromatic_adaptation_VonKries(np.asarray(white), np.asarray(D50), "Bradford")


def _is_srgb(curves, matrix) -> bool:
    from lenslab import srgb

    if np.abs(matrix - np.eye(3)).max() > SRGB_MATRIX_TOLERANCE:  # (other primaries: the curves need no look)
        return False
    x = np.linspace(0.0, 1.0, 4097)
    reference = srgb.cached_table("eotf-4097", 4097, np.float64, lambda: srgb.eotf(x))  # (no colour-science import)
    return all(np.abs(np.clip(fn(x), 0.0, 1.0) - reference).max() <= SRGB_CURVE_TOLERANCE for fn in curves)


def plan(data: bytes, channels: int, where: str) -> Plan:
    """What to do with profile ``data`` for an image of ``channels`` colour channels (1 grey, 3 RGB, 4 the CMYK
    inks of a JPEG that its decoder gives as RGB)."""
    tags = _tags(data, where)
    from PIL import ImageCms

    try:
        profile = ImageCms.ImageCmsProfile(io.BytesIO(data)).profile
        name = " ".join(str(profile.profile_description or "").split())[:60] or "unnamed"
        space = str(profile.xcolor_space).strip()
        pcs = str(profile.connection_space).strip()
    except (OSError, ValueError, TypeError) as exc:
        refuse(where, f"cannot be parsed by littleCMS ({' '.join(str(exc).split())[:60]})")
    label = f"ICC profile '{name}'"
    lut = [t.decode() for t in LUT_TAGS if t in tags]
    wanted = {3: "RGB", 1: "GRAY", 4: "CMYK"}.get(channels)
    if space == wanted == "CMYK":  # a CMYK JPEG, which the decoder turns into RGB by inverting its inks
        return Plan("ignored", f"{label} is for the JPEG's CMYK inks: not applied, the inks converted to RGB "
                    "without colour management (each inverted, times the inverted K), read as sRGB")
    if space != wanted:
        return Plan("ignored", f"{label} is for {space or '?'} data, the image is {wanted or channels}: "
                    "not applied, read as sRGB")
    if lut or pcs != "XYZ":
        return Plan("ignored", f"{label} is LUT-based ({', '.join(lut) or pcs + ' connection space'}): "
                    "not applied, read as sRGB")
    names = [b"kTRC"] if channels == 1 else [b"rTRC", b"gTRC", b"bTRC"]
    missing = [t.decode() for t in names + ([b"rXYZ", b"gXYZ", b"bXYZ"] if channels == 3 else []) if t not in tags]
    if missing:
        return Plan("ignored", f"{label} lacks {', '.join(missing)}: not applied, read as sRGB")
    curves = tuple(curve(data, tags[t], where) for t in names)
    for fn in curves:
        evaluate(fn, 4096, where)
    if channels == 1:
        return Plan("grey", f"{label}: its grey curve applied", curves)
    colorants = [_xyz(getattr(profile, f"{c}_colorant")) for c in ("red", "green", "blue")]
    if any(c is None for c in colorants):
        refuse(where, "has colorant tags littleCMS cannot read")
    chad = profile.chromatic_adaptation
    adapt = np.asarray(chad[0], np.float64) if chad else _bradford_to_d50(_xyz(profile.media_white_point))
    matrix = _to_rec709(np.stack(colorants, axis=1), adapt, where)
    if _is_srgb(curves, matrix):
        return Plan("srgb", f"{label}: sRGB, read as sRGB")
    return Plan("matrix", f"{label}: its curves and colorants applied, converted to linear Rec.709", curves, matrix,
                name)


def linear(how: Plan) -> bool:
    """Whether every curve of a matrix/TRC profile is the identity (within 1e-6): a linear profile, which float
    samples (linear light) follow too."""
    x = np.linspace(0.0, 1.0, 257)
    return how.kind == "matrix" and all(np.abs(np.asarray(fn(x)) - x).max() <= 1e-6 for fn in how.curves)


def decode(codes: np.ndarray, maxval: int, how: Plan, where: str) -> np.ndarray:
    """Integer samples H x W x C (colour first, alpha last for C = 2, 4) -> float32 linear Rec.709 by the
    profile's curves and matrix; alpha code / maxval."""
    c = codes.shape[-1]
    out = np.empty(codes.shape, np.float32)
    for i, fn in enumerate(how.curves):
        out[..., i] = evaluate(fn, maxval, where)[codes[..., i]]
    if c in (2, 4):
        out[..., -1] = codes[..., -1].astype(np.float32) / np.float32(maxval)
    if how.matrix is not None:
        from lenslab.io.colour.primaries import to_rec709

        to_rec709(out, how.matrix)
    return out
