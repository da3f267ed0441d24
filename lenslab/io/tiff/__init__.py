"""TIFF through ``tifffile``: float32, half, 16-bit and 8-bit samples, grey or RGB, with or without alpha.

Reading: the first image of the file (``meta["attributes"]["pages"]`` counts them), chunky or planar.
Float samples (32-bit, 16-bit half, 64-bit) are linear light; 8- and 16-bit unsigned integer samples
are sRGB-encoded like PNG's and decoded to linear (``raw=True`` gives code / maxval), with alpha
(an extra sample) kept linear. Alpha tagged associated (ExtraSamples 1) is read as it is; tagged
unassociated (2), its colour is straight and is premultiplied after decoding; an extra sample of unspecified
data (0: tifffile's default for grey plus one, a coordinate pair, a depth) is no alpha and every value is read as
stored, as OpenImageIO reads it.
Photometric interpretations other than grey (min-is-black) and RGB
(palette, YCbCr, CMYK, min-is-white) are refused with a FormatError.

Writing: ``sample_type="float"`` (default, 32-bit), ``"half"``, ``"uint16"`` or ``"uint8"`` (the
integer types sRGB-encoded unless ``raw=True``); half floats are made as an EXR's are (:mod:`lenslab.io.halves`):
finite values beyond +-65504 clamped there and counted in a ``HalfOverflowWarning``, infinities and NaN kept;
alpha is written as an extra sample, marked associated (premultiplied colour, as EXR's) for float and unassociated for integers (straight
colour, as PNG's: unpremultiplied before encoding);
``compression="zlib"`` (Adobe Deflate, default), ``"lzw"``, ``"zstd"`` or ``"none"``, with the
horizontal (integer) or floating-point predictor unless ``predictor=False``; ``icc``: an ICC profile written
as tag 34675 (read back, on integer samples, as :mod:`lenslab.io.colour.icc` says).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from lenslab.errors import FormatError, cause, clip
from lenslab.inputs.limits import check_size
from lenslab.io.alpha import premultiply

#: TIFF ExtraSamples: 1 associated alpha (premultiplied colour), 2 unassociated (straight colour); 0 is unspecified data
ASSOCIATED = 1
UNASSOCIATED = 2
SAMPLE_TYPES = {"float": np.float32, "half": np.float16, "uint16": np.uint16, "uint8": np.uint8}
COMPRESSIONS = {"zlib": "adobe_deflate", "deflate": "adobe_deflate", "lzw": "lzw", "zstd": "zstd", "none": None}


class TiffNote(UserWarning):
    """What tifffile logged while reading a TIFF (a tag it skipped: an offset beyond the file...); ``command_line``:
    the note as a command prints it after the file's name."""


def tifffile_notes() -> None:
    """Turn tifffile's log lines into notes (:class:`TiffNote`; a command prints the same one once) rather than
    lines of tifffile's own on standard error."""
    import logging
    import warnings

    log = logging.getLogger("tifffile")
    if any(getattr(h, "lenslab_notes", False) for h in log.handlers):
        return

    class Notes(logging.Handler):
        lenslab_notes = True

        def emit(self, record):
            message = record.getMessage()
            warning = TiffNote(f"tifffile: {(message.splitlines() or [''])[0][:200]}")
            warning.command_line = str(warning)
            warnings.warn(warning, stacklevel=2)

    log.addHandler(Notes())
    log.propagate = False


def _name(value) -> str:
    """A tifffile enum's name (an unknown code comes back as a plain int)."""
    return getattr(value, "name", None) or f"code {clip(value)}"


def read_tiff(path: Path, raw: bool = False) -> tuple[np.ndarray, dict]:
    try:
        return _read_tiff(path, raw)
    except FormatError:
        raise
    except (TypeError, ValueError, AttributeError, KeyError, IndexError, OverflowError) as exc:  # tags of a wrong type
        raise FormatError(f"{path}: the TIFF's tags are damaged ({type(exc).__name__}: {cause(exc, 60)})") from None


def _read_tiff(path: Path, raw: bool = False) -> tuple[np.ndarray, dict]:
    import tifffile

    tifffile_notes()
    try:
        tif = tifffile.TiffFile(path)
    except (tifffile.TiffFileError, ValueError, OSError) as exc:
        raise FormatError(f"{path}: not a readable TIFF ({cause(exc)})") from None
    with tif:
        if not tif.pages:
            raise FormatError(f"{path}: the TIFF holds no image")
        page = tif.pages.first
        photometric = _name(page.photometric)
        if photometric not in ("MINISBLACK", "RGB"):
            raise FormatError(f"{path}: TIFF with {photometric} photometric interpretation is not supported; "
                              "lenslab reads grey and RGB")
        check_size(path, int(page.imagewidth), int(page.imagelength), int(page.samplesperpixel))
        try:
            data = page.asarray()
        except Exception as exc:  # a codec failure inside tifffile/imagecodecs: damaged data
            raise FormatError(f"{path}: the TIFF's pixel data cannot be decoded ({cause(exc)})") from None
        axes = page.axes
        attrs = {"pages": len(tif.pages), "compression": _name(page.compression).lower(),
                 "photometric": photometric.lower(), "planar": "separate" if int(page.planarconfig) == 2 else "contig",
                 "extrasamples": [int(v) for v in page.extrasamples]}
        if page.description:
            attrs["description"] = page.description
        profile = _profile(page, path) if not raw else None
    if "S" in axes:
        data = np.moveaxis(data, axes.index("S"), -1)
        axes = axes.replace("S", "") + "S"
    while data.ndim > (3 if axes.endswith("S") else 2):  # depth or other leading axes: the first slice
        data = data[0]
    if data.ndim == 2:
        data = data[..., None]
    c = data.shape[2]
    if c > 4:
        data, c = data[..., :4], 4
    kind = data.dtype.kind
    gamut = None  # the wide primaries integer codes were converted from (lenslab.io.colour.gamut)
    if kind == "f":
        image = data.astype(np.float32, copy=False)  # float32 samples: no second copy
        if profile is not None:  # linear light: a linear matrix/TRC profile's colorants apply, its curves do not
            from lenslab.io.colour.icc import linear, plan
            from lenslab.io.colour.primaries import to_rec709

            how = plan(profile, c - 1 if c in (2, 4) else c, str(path))
            if linear(how):
                from lenslab.io.colour.gamut import negative_pixels, profile_gamut

                own = negative_pixels(image)  # negatives of the file's own: not the gamut's
                image = to_rec709(image if image.flags.writeable else image.copy(), how.matrix)
                attrs["icc"] = how.note
                gamut = profile_gamut(how) if not own else None
            else:
                attrs["icc"] = f"{how.note.split(':')[0]}: not applied, float samples are read as linear Rec.709"
        bits, sample, encoded = data.dtype.itemsize * 8, {2: "half", 4: "float", 8: "double"}[data.dtype.itemsize], False
    elif data.dtype in (np.uint8, np.uint16):
        from lenslab.io.encode import decode_codes

        bits, sample, encoded = data.dtype.itemsize * 8, "uint", not raw
        how = None
        if profile is not None:  # tag 34675: applied to integer samples as PNG's and JPEG's are
            from lenslab.io.colour.icc import decode, plan

            how = plan(profile, c - 1 if c in (2, 4) else c, str(path))
            attrs["icc"] = how.note
        if how is not None and how.curves:
            image = decode(data, np.iinfo(data.dtype).max, how, str(path))
            from lenslab.io.colour.gamut import profile_gamut

            gamut = profile_gamut(how)  # codes on other primaries
        else:
            image = decode_codes(data, np.iinfo(data.dtype).max, raw)
    else:
        raise FormatError(f"{path}: TIFF with {data.dtype} samples is not supported; lenslab reads float "
                          "(16, 32, 64-bit) and unsigned 8- and 16-bit samples")
    if c in (2, 4) and not raw and attrs["extrasamples"][:1] == [UNASSOCIATED]:
        premultiply(image)  # unassociated alpha: straight colour in the file. Unspecified data (0) is no alpha to
        # premultiply by (a second coordinate, a depth): its values as stored, as OpenImageIO reads them
    names = {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}[c]
    meta = {"format": "tiff", "bit_depth": bits, "sample_type": sample, "channels": names,
            "display_encoded": encoded, "attributes": attrs}
    if gamut:  # every negative component is a colour outside Rec.709's gamut (lenslab.io.colour.gamut)
        from lenslab.io.colour.gamut import WIDE_GAMUT

        meta[WIDE_GAMUT] = gamut
    return np.ascontiguousarray(image, dtype=np.float32), meta


def _profile(page, path) -> bytes | None:
    """The bytes of the page's ICC profile tag (34675), its size checked against the budget before reading."""
    from lenslab.io.colour.icc import MAX_BYTES, refuse

    tag = page.tags.get(34675)
    if tag is None:
        return None
    if tag.count > MAX_BYTES:
        refuse(str(path), f"tag declares {tag.count} bytes, more than the {MAX_BYTES >> 20} MiB a profile is read up to")
    return bytes(tag.value)


def write_tiff(tmp: Path, image: np.ndarray, sample_type: str = "float", compression: str = "zlib",
               predictor: bool = True, raw: bool = False, dither: bool = False, icc: bytes | None = None,
               exif: dict | None = None, in_place: bool = False) -> None:
    """Write ``image`` (float32 H x W x C) to ``tmp``; ``in_place``: the caller gives ``image`` up, and half floats or
    integer codes are made in its own memory (:func:`lenslab.io.halves.to_half`,
    :func:`lenslab.io.encode.encode_codes`). ``exif``: camera tags (:mod:`lenslab.io.exif`): Make, Model and
    Orientation in the first IFD, the rest in an Exif IFD written after the image."""
    import tifffile

    if sample_type not in SAMPLE_TYPES:
        raise FormatError(f"TIFF sample_type must be one of {', '.join(SAMPLE_TYPES)}, not {sample_type!r}")
    comp = str(compression).lower()
    if comp not in COMPRESSIONS:
        raise FormatError(f"unknown TIFF compression {compression!r}; choose one of {', '.join(COMPRESSIONS)}")
    c = image.shape[2]
    dtype = SAMPLE_TYPES[sample_type]
    alpha = c in (2, 4)
    if dtype is np.float16:  # clamped to +-65504 and counted, as an EXR's halves are
        from lenslab.io.halves import to_half

        data = to_half(image, in_place=in_place, fmt="TIFF", option="sample_type")
    elif np.dtype(dtype).kind == "f":
        data = image.astype(dtype, copy=False)  # (float32: the image itself, not a copy of its size)
    else:
        from lenslab.io.encode import encode_codes

        data = encode_codes(image, np.dtype(dtype).itemsize * 8, raw, dither, straight=not raw, in_place=in_place)
    options = {"photometric": "rgb" if c >= 3 else "minisblack", "compression": COMPRESSIONS[comp],
               "software": "lenslab", "metadata": None}
    if icc is not None:  # tag 34675: what the integer codes mean (a display's profile, lenslab.io.colour.icc_build)
        options["iccprofile"] = bytes(icc)
    if alpha:
        options["extrasamples"] = ["assocalpha" if np.dtype(dtype).kind == "f" else "unassalpha"]
    if predictor and COMPRESSIONS[comp] is not None:
        options["predictor"] = "floatingpoint" if np.dtype(dtype).kind == "f" else "horizontal"
    tifffile.imwrite(tmp, data if c > 1 else data[..., 0], **options)
    if exif:
        from lenslab.io.exif.outputs import append_exif_ifd

        append_exif_ifd(tmp, exif, srgb=np.dtype(dtype).kind != "f" and not raw and icc is None)
