"""JPG and PNG through OpenCV (``cv2.imdecode``/``cv2.imencode``), sRGB-encoded 8-bit (PNG also 16-bit).

OpenCV works in BGR order; images here are RGB. PNG alpha is straight (the PNG specification): the
colour is unpremultiplied before it is encoded and premultiplied after it is decoded, so memory holds
premultiplied colour (:mod:`lenslab.io.alpha`); ``raw=True`` reads and writes the stored values as
they are. A JPG's EXIF orientation is applied (:mod:`lenslab.io.exif_orientation`: the image as viewers show it,
``meta["attributes"]["orientation"]`` says how it was turned). An Ultra HDR JPEG (a gain map in an
MPF secondary image) reads as its HDR rendition, the gain map applied to the base image (:mod:`lenslab.io.gainmap`);
``selector="sdr"`` (``photo.jpg:sdr``) or ``raw=True`` reads the base image alone. An embedded ICC profile (PNG
``iCCP``, JPEG ``APP2``) is applied as :mod:`lenslab.io.colour.icc` says, unless a PNG's ``cICP`` chunk speaks
(it takes precedence).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from lenslab.errors import FormatError
from lenslab.inputs.limits import check_size


def _png_size(data: bytes) -> tuple[int, int] | None:
    if len(data) >= 24 and data[12:16] == b"IHDR":
        return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    return None


def _jpg_size(data: bytes) -> tuple[int, int] | None:
    """Width and height from the first start-of-frame marker, or None if none is found."""
    frame = _jpg_frame(data)
    return None if frame is None else frame[:2]


def _one_exif(data: bytes) -> tuple[bytes, int]:
    """``data`` (a PNG) without its eXIf chunks after the first, and how many there were: the PNG specification (3rd
    edition, 11.3.6) allows one, and libpng keeps the first and prints a warning per other on standard error. (Dropped
    before decoding, not captured: a capture of standard error is process-wide, and would take the lines of the other
    PNGs a batch decodes on threads at once.) Walked only where the bytes name eXIf twice."""
    first = data.find(b"eXIf")
    if first < 0 or data.find(b"eXIf", first + 4) < 0:
        return data, 0
    pos, n, parts, start, seen = 8, len(data), [], 8, 0
    while pos + 12 <= n:
        end = pos + 12 + int.from_bytes(data[pos:pos + 4], "big")
        kind = data[pos + 4:pos + 8]
        if end > n or kind == b"IEND":
            break
        if kind == b"eXIf":
            seen += 1
            if seen > 1:
                if pos > start:  # (only the chunks between: a run of eXIf chunks adds nothing)
                    parts.append(data[start:pos])
                start = end
        pos = end
    if seen < 2:
        return data, 0
    parts.append(data[start:])
    return data[:8] + b"".join(parts), seen - 1


def _decode(path, data: bytes, fmt: str):
    """OpenCV's decoding of ``data``; a PNG's repeated eXIf chunks dropped first, in one note."""
    import cv2

    if fmt == "png":
        data, dropped = _one_exif(data)
        if dropped:
            import warnings

            note = f"{dropped} duplicate eXIf chunks after the first are ignored (a PNG holds one)"
            warning = UserWarning(f"{path}: {note}")
            warning.command_line = note  # (a command's note names the file)
            warnings.warn(warning, stacklevel=3)
    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)


def _jpg_frame(data: bytes) -> tuple[int, int, int] | None:
    """Width, height and component count (3 YCbCr or RGB, 4 CMYK or YCCK) of the first start-of-frame."""
    pos, n = 2, len(data)
    while pos + 4 <= n:
        if data[pos] != 0xFF:
            return None
        marker = data[pos + 1]
        if marker == 0xFF:
            pos += 1
            continue
        length = int.from_bytes(data[pos + 2:pos + 4], "big")
        if 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC):
            if pos + 10 > n:
                return None
            return (int.from_bytes(data[pos + 7:pos + 9], "big"), int.from_bytes(data[pos + 5:pos + 7], "big"),
                    data[pos + 9])
        pos += 2 + length
    return None


def read_ldr(path: Path, fmt: str, raw: bool = False, selector: str | None = None) -> tuple[np.ndarray, dict]:
    import cv2

    sdr = fmt == "jpg" and _wants_sdr(path, selector)
    data = path.read_bytes()
    size = _png_size(data) if fmt == "png" else _jpg_size(data)
    if size is None:
        raise FormatError(f"{path}: the {fmt.upper()} header is missing or damaged")
    check_size(path, *size)
    if fmt == "jpg" and data.rfind(b"\xff\xd9") < 0:
        raise FormatError(f"{path}: the JPG has no end-of-image marker; it is truncated")
    if fmt == "png" and b"IEND" not in data[-32:]:
        raise FormatError(f"{path}: the PNG has no IEND chunk at its end; it is truncated")
    gain, attributes = _gain_map(data, path, raw, sdr) if fmt == "jpg" else (None, {})
    if "gain_map" in attributes and gain is None and not raw and not sdr:  # a command's user is told too
        import warnings

        warning = GainMapWarning(f"{path}: {attributes['gain_map']}")
        warning.command_line = attributes["gain_map"]
        warnings.warn(warning, stacklevel=3)
    points = None  # a PNG's cICP code points (lenslab.io.colour.coded decodes by them)
    if fmt == "png":
        from lenslab.io.colour.png_cicp import chunk_before_data, describe, read_cicp

        points = read_cicp(data)
        if points is not None:
            attributes["cICP"] = describe(points)
    profile = None  # an ICC profile, applied where no cICP chunk speaks (PNG 3rd edition: cICP wins)
    if not raw and (fmt == "jpg" or points is None):
        from lenslab.io.colour.icc_chunks import jpeg_profile, png_profile

        profile = (png_profile if fmt == "png" else jpeg_profile)(data, str(path))
        if profile is not None:  # a damaged profile is refused before the decoder warns of it
            from lenslab.io.colour.icc import check

            check(profile, str(path))
    elif not raw and fmt == "png" and chunk_before_data(data, b"iCCP") is not None:
        attributes["icc"] = "ICC profile present, not applied: the cICP chunk takes precedence"
    grey_alpha = False
    if fmt == "png":
        from lenslab.io.png_grey_alpha import is_grey_alpha

        grey_alpha = is_grey_alpha(data)
    inks = fmt == "jpg" and (_jpg_frame(data) or (0, 0, 3))[2] == 4  # CMYK: OpenCV decodes it to RGB
    orientation = 1
    if fmt == "jpg":
        from lenslab.io.exif_orientation import jpeg_orientation

        orientation = jpeg_orientation(data)
    codes = _decode(path, data, fmt)
    del data  # the file's bytes are not kept while the floats are made
    if codes is None:
        raise FormatError(f"{path}: OpenCV cannot decode this {fmt.upper()}; the file is damaged")
    if codes.ndim == 2:
        codes = codes[..., None]
    c = codes.shape[2]
    if grey_alpha and c == 4:  # OpenCV repeats the grey as B, G and R: keep one, and the alpha
        codes, c = codes[..., [0, 3]], 2
    if c == 3:
        codes = codes[..., ::-1]
    elif c == 4:
        codes = codes[..., [2, 1, 0, 3]]
    if codes.dtype == np.uint8:
        maxval, bits = 255, 8
    elif codes.dtype == np.uint16:
        maxval, bits = 65535, 16
    else:
        raise FormatError(f"{path}: {fmt.upper()} with {codes.dtype} samples is not supported; use 8 or 16 bits")
    from lenslab.io.colour.coded import decode

    image, linear, gamut = decode(codes, maxval, str(path), attributes, profile=profile, points=points,
                                  raw=raw, inks=inks)
    if gain is not None:  # linear light, SDR white 1.0: the HDR rendition
        from lenslab.io.gainmap.apply import application_matrix, apply_gain

        matrix = application_matrix(gain, profile, c, str(path))
        image = apply_gain(np.ascontiguousarray(image, dtype=np.float32), gain.codes, gain.meta, to_rec709=matrix)
        linear = True
    if orientation != 1:  # the image as shown (the gain map was applied in the stored frame, as it was coded)
        from lenslab.io.exif_orientation import TURNS, turn

        image = turn(image, orientation)
        attributes["orientation"] = f"EXIF orientation {orientation}: the stored image {TURNS[orientation]}, as shown"
    names = {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}[c]
    meta = {
        "format": fmt,
        "bit_depth": bits,
        "sample_type": "uint",
        "channels": names,
        "display_encoded": not raw and not linear,
        "attributes": attributes,
    }
    if orientation != 1:  # (a lens of the sensor's pixels warps the stored frame: lenslab.jobs.warp.cameras)
        meta["exif_orientation"] = orientation
    if gamut:
        from lenslab.io.colour.gamut import WIDE_GAMUT

        meta[WIDE_GAMUT] = gamut
    return np.ascontiguousarray(image, dtype=np.float32), meta


class GainMapWarning(UserWarning):
    """An image with a gain map was read as its SDR base image: its gain map (the HDR rendition) is not applied."""


def _wants_sdr(path, selector: str | None) -> bool:
    """Whether a JPEG's selector asks for its SDR base image (``:sdr``); ``:hdr`` or none: its HDR rendition."""
    from lenslab.io.gainmap import HDR, SDR

    if selector not in (None, SDR, HDR):
        raise FormatError(f"{path}: a JPEG takes the selector ':{SDR}' (an Ultra HDR JPEG's SDR base image) or "
                          f"':{HDR}' (its HDR rendition, the default), not ':{selector}'")
    return selector == SDR


def _gain_map(data: bytes, path, raw: bool, sdr: bool) -> tuple:
    """(the gain map to apply or None, the attributes that say which rendition is read and why)."""
    from lenslab.io import gainmap

    if not gainmap.present(data):
        return None, {}
    if raw or sdr:
        why = "raw code values" if raw else f"the ':{gainmap.SDR}' selector"
        return None, {"rendition": f"SDR base image ({why}); the gain map is not applied"}
    frame = _jpg_frame(data) or (0, 0, 3)
    try:
        gain = gainmap.prepare(data, (frame[0], frame[1], 1 if frame[2] == 1 else 3))
    except gainmap.Skipped as exc:
        if exc.hdr_base:
            return None, {"rendition": "HDR base image", "gain_map": f"Ultra HDR gain map present: {exc}"}
        return None, {"rendition": "SDR base image: the HDR rendition cannot be made (see gain_map)",
                      "gain_map": f"Ultra HDR gain map present and ignored ({exc}): this is the SDR base image "
                                  "(display-referred, not the HDR rendition)"}
    return gain, {"rendition": gainmap.rendition_note(gain), "gain_map": gain.describe()}


def encode_ldr(image: np.ndarray, fmt: str, raw: bool = False, quality: int = 95,
               subsampling: str | None = None, bits: int = 8, dither: bool = False,
               compression: int = 1, cicp=None, in_place: bool = False, icc: bytes | None = None,
               exif: dict | None = None):
    """Encode a float image (C = 1, 2 (grey and alpha), 3 or 4 for PNG; 1 or 3 for JPG) to JPG or PNG bytes
    (a bytes-like object: the encoder's own buffer, not copied).

    PNG ``compression`` is zlib's level 0..9; 1 (the default) is twice as fast as 3 for files about
    6 % larger. PNG ``cicp``: four H.273 code points written as a ``cICP`` chunk (an HDR display's
    encoding, :mod:`lenslab.io.colour.png_cicp`). ``icc``: an ICC profile's bytes, written as PNG's ``iCCP`` chunk or
    JPEG's ``APP2`` segments (:mod:`lenslab.io.colour.icc_chunks`). ``exif``: camera tags (:mod:`lenslab.io.exif`),
    written as PNG's ``eXIf`` chunk or JPEG's ``APP1 Exif`` segment. ``in_place``: the code values are made in the
    image's own memory (the caller gives it up; :func:`lenslab.io.encode.encode_codes`), so encoding holds no other
    array of the image's size than the file's bytes.
    """
    import cv2

    from lenslab.io.encode import encode_codes

    c = image.shape[2]
    if fmt == "jpg":
        if bits != 8:
            raise FormatError(f"JPG holds 8-bit samples only, not bits={bits}; use PNG for 16 bits")
        if not 0 <= int(quality) <= 100:
            raise FormatError(f"JPG quality must be 0..100, not {quality}")
    elif bits not in (8, 16):
        raise FormatError(f"PNG can be written with bits=8 or bits=16, not {bits!r}")
    # (unpremultiplied block by block)
    codes = encode_codes(image, bits, raw, dither, straight=not raw, in_place=in_place)
    if c == 2 and fmt == "png":  # grey and alpha: a file OpenCV cannot write
        from lenslab.io.png_grey_alpha import encode_grey_alpha

        return _tagged(encode_grey_alpha(codes, compression), fmt, cicp, icc, exif)
    if c in (3, 4):  # OpenCV's order, B G R (A): red and blue swapped in place, a band of rows at a time
        swap = cv2.COLOR_RGB2BGR if c == 3 else cv2.COLOR_RGBA2BGRA
        for r in range(0, codes.shape[0], 64):
            band = codes[r:r + 64]
            cv2.cvtColor(band, swap, dst=band)
    if fmt == "jpg":
        sub = subsampling or ("444" if int(quality) >= 90 else "420")
        factors = {"444": cv2.IMWRITE_JPEG_SAMPLING_FACTOR_444, "422": cv2.IMWRITE_JPEG_SAMPLING_FACTOR_422,
                   "420": cv2.IMWRITE_JPEG_SAMPLING_FACTOR_420, "411": cv2.IMWRITE_JPEG_SAMPLING_FACTOR_411,
                   "440": cv2.IMWRITE_JPEG_SAMPLING_FACTOR_440}
        key = str(sub).replace(":", "")
        if key not in factors:
            raise FormatError(f"unknown JPG chroma subsampling {subsampling!r}; choose 444, 422 or 420")
        params = [cv2.IMWRITE_JPEG_QUALITY, int(quality), cv2.IMWRITE_JPEG_SAMPLING_FACTOR, factors[key]]
        ok, buf = cv2.imencode(".jpg", codes, params)
    else:
        ok, buf = cv2.imencode(".png", codes, [cv2.IMWRITE_PNG_COMPRESSION, int(compression)])
    if not ok:
        raise FormatError(f"OpenCV could not encode the image as {fmt.upper()}")
    del codes
    if cicp is not None or icc is not None or exif:
        return _tagged(buf.tobytes(), fmt, cicp, icc, exif)
    return memoryview(buf).cast("B")


def _tagged(encoded: bytes, fmt: str, cicp, icc, exif=None) -> bytes:
    """``encoded`` with its ``cICP`` chunk (PNG only), its ICC profile and its camera tags (before the profile)."""
    from lenslab.io.colour.icc_chunks import jpeg_with_profile, png_with_profile
    from lenslab.io.colour.png_cicp import with_cicp

    if cicp is not None and fmt != "png":
        raise FormatError("only PNG carries a cICP chunk")
    try:
        out = encoded if cicp is None else with_cicp(encoded, cicp)
        if icc is not None:
            out = png_with_profile(out, icc) if fmt == "png" else jpeg_with_profile(out, icc)
        if exif:
            from lenslab.io.exif.outputs import jpeg_with_exif, png_with_exif

            out = png_with_exif(out, exif) if fmt == "png" else jpeg_with_exif(out, exif, srgb=icc is None)
        return out
    except ValueError as exc:
        raise FormatError(str(exc)) from None
