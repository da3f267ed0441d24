"""Image files in and out: EXR, PFM, PPM/PGM/PBM, JPG and PNG.

``read(path) -> (image, meta)``: ``image`` is float32 ``H x W x C`` in linear light (LDR formats are
decoded from sRGB; ``raw=True`` gives code values scaled to [0, 1] instead). The format comes from the
file's magic bytes, never its name. ``meta`` holds ``format``, ``bit_depth``, ``sample_type``,
``channels``, ``display_encoded``, ``attributes`` (what the file carried), ``size`` (W, H), ``path``
and ``camera`` (a :class:`lenslab.lenses.Camera` if the file stores one, else None).

EXR selectors: ``"file.exr:left"`` (a layer), ``"file.exr:2"`` or ``"file.exr:rgba_left"`` (a part),
``"file.exr:2:left"`` (both). Read options: ``data_window=True`` keeps an EXR's stored data window
instead of placing it in the display window; ``rec709=False`` keeps an EXR's own primaries. PFM's
scale is reported in ``meta["attributes"]["scale"]`` and never applied. Sizes beyond
:data:`lenslab.io.limits.MAX_PIXELS` are refused before any allocation.

``write(path, image, format=None, **options)``: the format from ``format=`` or the extension; the
file is written to a temporary name and renamed (see :mod:`lenslab.io.atomic`). Options:

- all: ``overwrite=True``; ``camera=`` (EXR stores it as the ``lenslab.camera`` TOML attribute)
- LDR (ppm/pgm/jpg/png): ``raw=False`` (True: values are code values / maxval, no sRGB encoding),
  ``dither=False``; ``bits=8|16`` (PPM/PGM, PNG); ``ascii=False`` (P3/P2 instead of P6/P5);
  ``quality=95`` and ``subsampling="444"|"422"|"420"`` (JPG; 4:4:4 by default at quality >= 90);
  ``compression=1`` (PNG zlib level)
- PFM: ``byte_order="little"|"big"``, ``scale=1.0``
- EXR: ``pixel_type="half"|"float"``, ``compression="zip"`` (see ``lenslab.io.exr.COMPRESSIONS``),
  ``channels=[names]``, ``attributes={name: value}``

Formats without alpha (PPM, PFM, JPG) drop the alpha channel; PGM and ``Pf`` hold one channel.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError
from lenslab.io.atomic import atomic_write_path
from lenslab.io.detect import HDR_FORMATS, format_for_path, sniff
from lenslab.io.exr import CAMERA_ATTRIBUTE, HalfOverflowWarning

__all__ = ["read", "write", "split_selector", "FormatError", "HalfOverflowWarning", "CameraAttributeWarning",
           "atomic_write_path", "HDR_FORMATS", "sniff"]


def split_selector(path: str | os.PathLike) -> tuple[Path, str | None]:
    """``"a.exr:left"`` -> (Path("a.exr"), "left") when ``a.exr`` exists and ``a.exr:left`` does not."""
    text = os.fspath(path)
    if os.path.exists(text) or ":" not in text:
        return Path(text), None
    i = text.find(":")
    while i >= 0:
        head = text[:i]
        if head and os.path.isfile(head):
            return Path(head), text[i + 1:]
        i = text.find(":", i + 1)
    return Path(text), None


class CameraAttributeWarning(UserWarning):
    """A file's ``lenslab.camera`` attribute could not be turned into a camera (the pixels still read)."""


def _camera(path, text):
    if not text:
        return None
    from lenslab.errors import LensError
    from lenslab.lenses import Camera

    try:
        return Camera.from_toml(str(text))
    except (LensError, KeyError, TypeError, ValueError) as exc:
        warnings.warn(f"{path}: the {CAMERA_ATTRIBUTE} attribute is not a camera this lenslab understands "
                      f"({exc}); meta['camera'] is None", CameraAttributeWarning, stacklevel=3)
        return None


def read(path: str | os.PathLike, *, raw: bool = False, data_window: bool = False,
         rec709: bool = True) -> tuple[np.ndarray, dict]:
    """Read an image file -> (float32 H x W x C array, meta). See the module docstring."""
    file, selector = split_selector(path)
    fmt = sniff(file)
    if selector is not None and fmt != "exr":
        raise FormatError(f"{file}: a ':{selector}' selector only applies to EXR files (this is {fmt.upper()})")
    if fmt == "exr":
        from lenslab.io.exr import read_exr
        image, meta = read_exr(file, selector, data_window=data_window, rec709=rec709)
    elif fmt == "pfm":
        from lenslab.io.pfm import read_pfm
        image, meta = read_pfm(file)
    elif fmt == "pnm":
        from lenslab.io.pnm import read_pnm
        image, meta = read_pnm(file, raw=raw)
    else:
        from lenslab.io.ldr import read_ldr
        image, meta = read_ldr(file, fmt, raw=raw)
    meta["path"] = str(file)
    meta["size"] = [int(image.shape[1]), int(image.shape[0])]
    meta["camera"] = _camera(file, meta["attributes"].get(CAMERA_ATTRIBUTE))
    return image, meta


def _as_image(array) -> np.ndarray:
    a = np.asarray(array)
    if a.dtype.kind not in "fiub":
        raise FormatError(f"cannot write an array of dtype {a.dtype}; give a float32 image H x W x C")
    if a.ndim == 2:
        a = a[..., None]
    if a.ndim != 3 or a.shape[0] == 0 or a.shape[1] == 0:
        raise FormatError(f"cannot write an array of shape {a.shape}; give an image H x W x C")
    if a.shape[2] not in (1, 2, 3, 4):
        raise FormatError(f"cannot write {a.shape[2]} channels as an image; give 1, 3 or 4 (EXR: any, with "
                          "channels=[names])")
    return a.astype(np.float32, copy=False)


def _fit_channels(a: np.ndarray, fmt: str) -> np.ndarray:
    c = a.shape[2]
    if fmt == "pgm":
        if c == 1:
            return a
        raise FormatError(f"PGM holds one channel; this image has {c}: write PPM, or keep one channel")
    if fmt in ("ppm", "jpg", "pfm"):  # no alpha in these formats: colour (or grey) only
        if c == 4:
            return a[..., :3]
        if c == 2:
            return a[..., :1]
        return a
    if fmt == "png" and c == 2:
        raise FormatError("PNG cannot hold two channels here; give 1, 3 or 4")
    return a


def write(path: str | os.PathLike, array, format: str | None = None, *, overwrite: bool = True,
          camera=None, **options) -> Path:
    """Write an image; returns the path written. See the module docstring for the options."""
    target = Path(path)
    fmt = format_for_path(target, format)
    image = _as_image(array) if not (fmt == "exr" and "channels" in options) else np.asarray(array, np.float32)
    if image.ndim == 2:
        image = image[..., None]
    image = _fit_channels(image, fmt)
    if fmt == "ppm" and image.shape[2] == 1 and target.suffix.lower() == ".ppm":
        image = np.repeat(image, 3, axis=2)  # a .ppm is colour; grey goes to .pgm
    if fmt == "ppm" and image.shape[2] == 1:
        fmt = "pgm"

    def unknown(allowed: set[str]):
        extra = set(options) - allowed
        if extra:
            raise FormatError(f"unknown option(s) for {fmt.upper()}: {', '.join(sorted(extra))}; allowed: "
                              f"{', '.join(sorted(allowed))}")

    if camera is not None and fmt != "exr":
        raise FormatError(f"{fmt.upper()} cannot store a camera; write EXR to keep the lens model with the image")
    with atomic_write_path(target, overwrite=overwrite) as tmp:
        if fmt == "exr":
            unknown({"pixel_type", "compression", "channels", "attributes", "threads"})
            from lenslab.io.exr import write_exr
            write_exr(tmp, image, camera=camera, **options)
        elif fmt == "pfm":
            unknown({"byte_order", "scale"})
            from lenslab.io.pfm import write_pfm
            write_pfm(tmp, image, **options)
        elif fmt in ("ppm", "pgm"):
            unknown({"bits", "ascii", "raw", "dither"})
            from lenslab.io.pnm import encode_pnm
            tmp.write_bytes(encode_pnm(image, **options))
        else:
            unknown({"raw", "quality", "subsampling", "bits", "dither", "compression"})
            from lenslab.io.ldr import encode_ldr
            tmp.write_bytes(encode_ldr(image, fmt, **options))
    return target
