"""HEIF and HEIC still images (ISO/IEC 23008-12, the files phones write), read through pillow-heif (libheif and
libde265; the ``lenslab[heif]`` extra, imported only when a HEIF file is read).

- **Which image**: a file holds one or more top-level images; the primary one is read, another by its index
  in the file (``photo.heic:1``, the selector of EXR parts), and ``meta["attributes"]["images"]`` lists them
  all. libheif applies the container's rotation, mirror and crop (``irot``, ``imir``, ``clap``) and puts a
  grid's tiles together: the image is the one a viewer shows.
- **Samples**: 8-bit codes as they are, 10- and 12-bit codes at their own depth (pillow-heif's
  ``hdr_to_16bit=False``: its 16-bit output is the code shifted left, ``c << 6`` for 10 bits, whose value
  over 65535 is up to one 10-bit step below ``c / 1023``, the code value H.273 defines). libheif has already
  turned Y'CbCr into full-range R'G'B' by the ``nclx`` matrix coefficients and range.
- **Colour** (:mod:`lenslab.io.colour.coded`, the one way of PNG and JPEG too): an ICC profile (``colr``
  ``prof``/``rICC``; pillow-heif exposes it in place of an ``nclx`` when a file holds both) is applied as in
  a PNG; else the ``nclx`` code points: PQ and HLG to linear light as lenslab's video path does (1.0 =
  203 cd/m², BT.2020 and P3-D65 primaries converted to Rec.709), sRGB and BT.709 transfers sRGB-decoded,
  wide primaries converted; a file without colour information, or whose ``nclx`` leaves the transfer
  unspecified, is sRGB (MIAF's default: primaries 1, transfer 13, full range).
- **Alpha** (an alpha auxiliary image): coverage, code / maxval; straight colour in the file (premultiplied
  when its ``prem`` reference says so) becomes premultiplied colour in memory (:mod:`lenslab.io.alpha`).
- **Ignored, with a note**: depth images, gain maps (Apple's HDR gain map and other auxiliary images:
  :class:`lenslab.io.ldr.GainMapWarning`, as for an Ultra HDR JPEG whose gain map cannot be applied), thumbnails, EXIF and XMP.
- **Budget**: the declared size of the image to read against the file's bytes
  (:func:`lenslab.io.budget.check`) before any pixel is decoded. HEVC codes a flat picture in a few bytes per
  64 x 64 block, so no floor of bytes per pixel is claimed; the rule on the file's bytes applies
  (:func:`lenslab.io.budget.allowed`).
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from lenslab.errors import FormatError, cause

#: what the notes name as the source of H.273 code points
NCLX = "the HEIF's nclx colour information"
EXTRA = "pip install 'lenslab[heif]'"
#: H.273 transfer characteristics that name no curve (reserved, unspecified): read as MIAF's default, sRGB
UNSPECIFIED = (0, 2)


def _library(path):
    try:
        import pillow_heif
    except ImportError:
        raise FormatError(f"{path}: reading HEIF/HEIC needs pillow-heif: {EXTRA}") from None
    return pillow_heif


def open_file(path):
    """pillow-heif's ``HeifFile`` of ``path``, its container parsed and nothing decoded; one-line FormatError for
    a file libheif cannot parse."""
    pillow_heif = _library(path)
    try:
        heif = pillow_heif.open_heif(os.fspath(path), convert_hdr_to_8bit=False, hdr_to_16bit=False)
    except (ValueError, EOFError, SyntaxError, RuntimeError, OSError) as exc:
        raise FormatError(f"{path}: libheif cannot read it as HEIF ({cause(exc)}); the file is damaged, truncated "
                          "or not a HEIF image") from None
    if len(heif) == 0:
        raise FormatError(f"{path}: the HEIF file holds no still image (an image sequence or a damaged file)")
    return heif


def _channels(mode: str) -> int:
    """Channels of a pillow-heif mode (``RGB;10``, ``RGBA``, ``RGBa``, ``L``, ``LA;12``)."""
    base = mode.split(";")[0]
    if base in ("L", "I"):
        return 1
    return {"LA": 2, "La": 2, "RGB": 3, "BGR": 3, "RGBA": 4, "RGBa": 4, "BGRA": 4, "BGRa": 4}.get(base, 0)


def pick(path, heif, selector: str | None) -> int:
    """The index of the image to read: the primary one, or the selector's (a top-level image's index)."""
    if not selector:
        return heif.primary_index
    if selector.isdigit() and int(selector) < len(heif):
        return int(selector)
    raise FormatError(f"{path}: no image {selector!r}; the file holds {len(heif)} top-level image(s): "
                      f"{listing(heif)}; pick one as {os.path.basename(path)}:INDEX")


def listing(heif) -> str:
    """``0: 24 x 16, 1: 8 x 6 (primary)``: every top-level image's index and size, the primary named."""
    shown = [f"{i}: {im.size[0]} x {im.size[1]}{' (primary)' if i == heif.primary_index else ''}"
             for i, im in enumerate(list(heif)[:8])]
    return ", ".join(shown) + (f" and {len(heif) - 8} more" if len(heif) > 8 else "")


def declare(path, **_):
    """The primary image's size and channels (:class:`lenslab.io.budget.Declared`), from the container alone."""
    from lenslab.io.budget import Declared

    heif = open_file(path)
    image = heif[heif.primary_index]
    return Declared(*image.size, max(1, _channels(image.mode)), what="HEVC data", parsed=heif)


class MultiImageWarning(UserWarning):
    """A HEIF file with several top-level images read without a selector: its primary image is read, and the
    note names the others. ``command_line``: the note without the path."""


def _notes(path, heif, index: int, selector, info: dict, attributes: dict, raw: bool) -> None:
    """What the file holds beside the image read: the other images, depth images, gain maps and other
    auxiliary images, thumbnails; the command's notes (warnings) for what changes a result."""
    attributes["images"] = f"{len(heif)} top-level images ({listing(heif)}); read {index}" if len(heif) > 1 \
        else "1 top-level image"
    if len(heif) > 1:
        if not selector:
            note = (f"holds {len(heif)} top-level images ({listing(heif)}); read the primary one, {index}; pick "
                    f"another as {os.path.basename(path)}:INDEX")
            warning = MultiImageWarning(f"{path}: {note}")
            warning.command_line = note
            warnings.warn(warning, stacklevel=4)
    depth = info.get("depth_images") or []
    if depth:
        attributes["depth"] = f"{len(depth)} depth image(s) present and ignored"
    aux = {str(k): len(v) for k, v in (info.get("aux") or {}).items()}
    gain = [k for k in aux if "gainmap" in k.lower().replace("-", "").replace("_", "")]
    if gain:
        from lenslab.io.ldr import GainMapWarning

        attributes["gain_map"] = (f"HDR gain map present and ignored ({', '.join(gain)}): this is the SDR base image "
                                  "(display-referred, not the HDR rendition)")
        if not raw:
            warning = GainMapWarning(f"{path}: {attributes['gain_map']}")
            warning.command_line = attributes["gain_map"]
            warnings.warn(warning, stacklevel=4)
    others = [k for k in aux if k not in gain]
    if others:
        attributes["auxiliary"] = f"auxiliary image(s) present and ignored: {', '.join(others)}"
    if info.get("thumbnails"):
        attributes["thumbnails"] = f"{len(info['thumbnails'])} thumbnail(s), not read"


def _decode(path, image) -> np.ndarray:
    try:
        codes = np.asarray(image)
    except (ValueError, EOFError, SyntaxError, RuntimeError, OSError) as exc:
        raise FormatError(f"{path}: libheif cannot decode the image ({cause(exc)}); the file is truncated or "
                          "damaged") from None
    return codes[..., None] if codes.ndim == 2 else codes


def _straight(codes: np.ndarray, maxval: int) -> np.ndarray:
    """Colour codes premultiplied by alpha (a ``prem`` reference) -> straight codes, rounded (0 where alpha is)."""
    alpha = codes[..., -1:].astype(np.float64)
    colour = np.divide(codes[..., :-1] * float(maxval), alpha, out=np.zeros(codes[..., :-1].shape), where=alpha > 0)
    out = codes.copy()
    out[..., :-1] = np.clip(np.rint(colour), 0, maxval).astype(codes.dtype)
    return out


def read_heif(path, selector: str | None = None, raw: bool = False, parsed=None) -> tuple[np.ndarray, dict]:
    """The image of a HEIF file (the primary one, or the ``selector``'s): float32 H x W x C, linear light
    (``raw``: code / maxval), and its meta (see the module docstring)."""
    heif = parsed if parsed is not None else open_file(path)
    index = pick(path, heif, selector)
    image = heif[index]
    if index != heif.primary_index:  # the budget looked at the primary image: this one is looked at here
        from lenslab.io.budget import Declared, check, regular_size

        check(path, Declared(*image.size, max(1, _channels(image.mode))), regular_size(path))
    channels = _channels(image.mode)
    if channels == 0:
        raise FormatError(f"{path}: pillow-heif gives the image in mode {image.mode!r}, which lenslab does not read")
    info = image.info
    bits = int(info.get("bit_depth") or 8)
    attributes: dict = {}
    _notes(path, heif, index, selector, info, attributes, raw)
    nclx = info.get("nclx_profile")
    points = None
    if nclx:
        points = tuple(int(nclx.get(k, d)) for k, d in (("color_primaries", 2), ("transfer_characteristics", 2),
                                                           ("matrix_coefficients", 2), ("full_range_flag", 1)))
        from lenslab.io.colour.png_cicp import describe

        attributes["nclx"] = describe(points)
        if points[1] in UNSPECIFIED:  # no curve named: sRGB, as a file without colour information is
            points = (points[0], 13, *points[2:])
            attributes["nclx"] += "; the transfer unspecified: read as sRGB (MIAF's default)"
    else:
        attributes["nclx"] = "none: sRGB (MIAF's default, primaries 1, transfer 13, full range)"
    profile = info.get("icc_profile") or None
    if profile is not None:
        attributes["icc_profile"] = f"{info.get('icc_profile_type', 'ICC')}, {len(profile)} bytes"
        if raw:
            profile = None
        else:
            from lenslab.io.colour.icc import check

            check(bytes(profile), str(path))  # a damaged profile is refused before any pixel is decoded
            profile = bytes(profile)
    codes = _decode(path, image)
    if codes.shape[2] != channels:
        raise FormatError(f"{path}: libheif gave {codes.shape[2]} channels for mode {image.mode!r}; the file is "
                          "damaged")
    maxval = (1 << bits) - 1
    if int(codes.max(initial=0)) > maxval:
        raise FormatError(f"{path}: the decoded codes pass the {bits}-bit range; the file is damaged")
    if image.premultiplied_alpha and not raw:
        codes = _straight(codes, maxval)
        attributes["alpha"] = "premultiplied in the file (prem), premultiplied in linear light here"
    from lenslab.io.colour.coded import decode

    decoded, linear, gamut = decode(codes, maxval, str(path), attributes, profile=profile, points=points,
                                    raw=raw, source=NCLX)
    del codes
    names = {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}[channels]
    meta = {"format": "heif", "bit_depth": bits, "sample_type": "uint", "channels": names,
            "display_encoded": not raw and not linear, "attributes": attributes}
    if len(heif) > 1:
        meta["image_index"] = index
    if gamut:
        from lenslab.io.colour.gamut import WIDE_GAMUT

        meta[WIDE_GAMUT] = gamut
    return np.ascontiguousarray(decoded, dtype=np.float32), meta
