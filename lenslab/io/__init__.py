"""Image files in and out: every format of :mod:`lenslab.io.registry` (EXR, Radiance HDR, TIFF, PFM,
PPM/PGM/PBM, JPG, PNG; HEIF/HEIC read only; ``lenslab info --formats`` lists them with what each holds).

``read(path) -> (image, meta)``: ``image`` is float32 ``H x W x C`` in linear light (LDR formats are
decoded from sRGB; ``raw=True`` gives code values scaled to [0, 1] instead). The format comes from the
file's magic bytes, never its name. ``meta`` holds ``format``, ``bit_depth``, ``sample_type``,
``channels``, ``display_encoded``, ``attributes`` (what the file carried), ``size`` (W, H), ``path``
and ``camera`` (a :class:`lenslab.lenses.Camera` if the file stores one, else None).

EXR selectors: ``"file.exr:left"`` (a layer), ``"file.exr:2"`` or ``"file.exr:rgba_left"`` (a part),
``"file.exr:2:left"`` (both); HEIF: ``"photo.heic:1"`` (a top-level image by its index; the primary without); JPEG: ``"photo.jpg:sdr"`` (an Ultra
HDR JPEG's SDR base image; without it, its HDR rendition: :mod:`lenslab.io.gainmap`). Read options: ``data_window=True`` keeps an EXR's stored data window
instead of placing it in the display window; ``rec709=False`` keeps an EXR's own primaries. PFM's
scale is reported in ``meta["attributes"]["scale"]`` and never applied. Sizes beyond
:data:`lenslab.inputs.limits.MAX_PIXELS` are refused before any allocation.

``write(path, image, format=None, **options)``: the format from ``format=`` or the extension; the
file is written to a temporary name and renamed (see :mod:`lenslab.atomic`). Options:

- all: ``overwrite=True``; ``camera=`` (EXR stores it as the ``lenslab.camera`` TOML attribute)
- LDR (ppm/pgm/jpg/png): ``raw=False`` (True: values are code values / maxval, no sRGB encoding),
  ``dither=False``; ``bits=8|16`` (PPM/PGM, PNG); ``ascii=False`` (P3/P2 instead of P6/P5);
  ``quality=95`` and ``subsampling="444"|"422"|"420"`` (JPG; 4:4:4 by default at quality >= 90);
  ``compression=1`` (PNG zlib level)
- PFM: ``byte_order="little"|"big"``, ``scale=1.0``
- EXR: ``pixel_type="half"|"float"``, ``compression="zip"`` (see ``lenslab.io.exr.COMPRESSIONS``),
  ``channels=[names]``, ``attributes={name: value}``

Alpha is the last channel and, where the file names its channels (EXR), only a channel named ``A``
(:func:`carries_alpha`; ``u, v`` are two data channels); names go back to an EXR writer through
:func:`output_channels`. Images with alpha hold premultiplied colour in memory; PNG and 8/16-bit
TIFF store straight colour and are converted when written and read, EXR and float TIFF store it as it
is (:mod:`lenslab.io.alpha`). Formats without alpha (PPM, PFM, JPG) drop the alpha channel (the image
over black); PGM and ``Pf`` hold one channel.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any


from lenslab.errors import FormatError, cause
from lenslab.atomic import atomic_write_path
from lenslab.io.registry import format_for_path, formats, get, hdr_formats, sniff

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike

    from lenslab.lenses import Camera

#: the EXR attribute holding a lenslab camera (TOML)
CAMERA_ATTRIBUTE = "lenslab.camera"


def __getattr__(name):  # the EXR codec (and NumPy) load only when used: commands start at once
    if name == "HalfOverflowWarning":
        from lenslab.io.halves import HalfOverflowWarning

        return HalfOverflowWarning
    raise AttributeError(f"module 'lenslab.io' has no attribute {name!r}")

__all__ = ["read", "write", "split_selector", "output_channels", "is_alpha_name", "carries_alpha",
           "FormatError", "HalfOverflowWarning", "CameraAttributeWarning",
           "atomic_write_path", "HDR_FORMATS", "sniff", "formats"]

#: formats holding linear floats (high dynamic range); the others hold display-encoded codes
HDR_FORMATS = hdr_formats()


def split_selector(path: str | os.PathLike) -> tuple[Path, str | None]:
    """Split an EXR selector from a path: ``"a.exr:left"`` -> (Path("a.exr"), "left").

    Only when ``a.exr`` is a file and ``a.exr:left`` does not exist: a file name with a colon in it
    stays whole.

    Parameters
    ----------
    path : str or os.PathLike
        A path, perhaps followed by ``:layer``, ``:part`` or ``:part:layer``.

    Returns
    -------
    tuple of (pathlib.Path, str or None)
        The file and the selector (None without one).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from lenslab.io import split_selector
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "stereo.exr"
    >>> _ = path.write_bytes(b"")
    >>> split_selector(f"{path}:2:left") == (path, "2:left")
    True
    >>> split_selector("missing.exr:left")[1] is None  # no file "missing.exr": no selector either
    True
    """
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
        note = f"the {CAMERA_ATTRIBUTE} attribute is not a camera this lenslab understands ({cause(exc)})"
        warning = CameraAttributeWarning(f"{path}: {note}; meta['camera'] is None")
        warning.command_line = note  # (a command's note names the file)
        warnings.warn(warning, stacklevel=3)
        return None


def read(path: str | os.PathLike, *, raw: bool = False, data_window: bool = False,
         rec709: bool = True, extra_channels: bool = False) -> tuple[np.ndarray, dict[str, Any]]:
    """Read an image file into linear float32.

    The format comes from the file's magic bytes, never its name.

    Parameters
    ----------
    path : str or os.PathLike
        The file. EXR selectors pick a layer or part: ``"f.exr:left"``, ``"f.exr:2"``, ``"f.exr:2:left"``;
        ``"photo.jpg:sdr"`` an Ultra HDR JPEG's SDR base image (its HDR rendition without).
    raw : bool
        LDR formats: code values scaled to [0, 1] instead of decoding sRGB to linear light.
    data_window : bool
        EXR: keep the stored data window instead of placing it in the display window.
    rec709 : bool
        EXR: convert the file's own primaries to Rec.709 (False keeps them).
    extra_channels : bool
        EXR: also keep the part's other channels (``Z``, ``N.x``...; always named in
        ``meta["extra_channels"]``) as ``meta["extra_planes"]``, which an EXR writer's ``extra`` takes back.

    Returns
    -------
    image : numpy.ndarray
        float32 ``H x W x C`` in linear light (``C`` is 1 to 4; a last channel named ``A`` is alpha, with the
        colour premultiplied by it).
    meta : dict
        ``format``, ``bit_depth``, ``sample_type``, ``channels``, ``display_encoded``, ``attributes``
        (what the file carried; a PFM's scale is reported there, never applied), ``size`` (W, H),
        ``path`` and ``camera`` (a :class:`lenslab.lenses.Camera` when the file stores one, else None).

    Raises
    ------
    lenslab.errors.FormatError
        The file is not an image lenslab reads, is damaged, or is larger than
        :data:`lenslab.inputs.limits.MAX_PIXELS` (refused before any allocation).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np, lenslab
    >>> tmp = pathlib.Path(tempfile.mkdtemp())
    >>> path = lenslab.write(tmp / "grey.pfm", np.full((2, 3, 3), 0.5, np.float32))
    >>> image, meta = lenslab.read(path)
    >>> image.shape, image.dtype, meta["format"], meta["size"]
    ((2, 3, 3), dtype('float32'), 'pfm', [3, 2])
    """
    file, selector = split_selector(path)
    fmt = get(sniff(file))
    if selector is not None and not fmt.selectors:
        from lenslab.io import registry  # (the name formats here is also the plugins' package)

        names = [f.name.upper() for f in registry.formats().values() if f.selectors]
        takers = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]
        raise FormatError(f"{file}: a ':{selector}' selector only applies to {takers} files (this is {fmt.title})")
    given = {"raw": raw, "data_window": data_window, "rec709": rec709, "extra_channels": extra_channels}
    from lenslab.io.budget import admit

    declared = admit(file, fmt, **({"data_window": data_window} if "data_window" in fmt.read_options else {}))
    options = {k: given[k] for k in fmt.read_options if k in given}
    if declared is not None and declared.parsed is not None:
        options["parsed"] = declared.parsed  # the header the budget read: not parsed a second time
    image, meta = fmt.read(file, selector, **options)
    meta["path"] = str(file)
    meta["size"] = [int(image.shape[1]), int(image.shape[0])]
    meta["camera"] = _camera(file, meta["attributes"].get(CAMERA_ATTRIBUTE))
    return image, meta


def _as_image(array) -> "np.ndarray":
    import numpy as np

    from lenslab.errors import check_image_shape

    a = check_image_shape(array, "an image to write", channels=None)
    if a.ndim == 2:
        a = a[..., None]
    return a.astype(np.float32, copy=False)


def with_alpha(image: np.ndarray, alpha: ArrayLike) -> np.ndarray:
    """``image`` (``H x W x C``, grey or RGB) with ``alpha`` (``H x W``) stacked as its last channel, float32."""
    import numpy as np

    a = np.asarray(alpha, dtype=np.float32)
    if a.ndim == 3 and a.shape[2] == 1:
        a = a[..., 0]
    if a.shape != image.shape[:2]:
        raise FormatError(f"alpha of shape {a.shape} does not match the image's {image.shape[0]} x {image.shape[1]}; "
                          "give an H x W array")
    if image.shape[2] not in (1, 3):
        raise FormatError(f"the image already has {image.shape[2]} channels; give alpha only with grey or RGB")
    return np.concatenate([image, a[..., None]], axis=2)


#: channel names an EXR writer gives an image that carries none, by channel count
DEFAULT_CHANNELS = {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}


def is_alpha_name(name: str) -> bool:
    """Whether a channel of this name is alpha: ``A``, or ``A`` of a layer (``left.A``), as OpenImageIO
    and compositors read it; any other channel holds data."""
    return isinstance(name, str) and name.rsplit(".", 1)[-1] == "A"


def carries_alpha(meta: dict, count: int) -> bool:
    """Whether an image of ``count`` channels made from an input described by ``meta`` (what :func:`read`
    gave) carries alpha last: the one alpha rule of every command. Where the channels have names, the last
    of the names the image is written with (:func:`output_channels`: the input's own names, or those and
    the ``A`` a warp adds to an image without alpha) is ``A`` (or ``layer.A``); else (no names) 2 or 4
    channels (:func:`lenslab.io.alpha.alpha_last`).

    >>> carries_alpha({"channels": ["u", "v"]}, 2), carries_alpha({"channels": ["Y", "A"]}, 2), carries_alpha({}, 4)
    (False, True, True)
    >>> carries_alpha({"channels": ["u", "v"]}, 3)  # u, v and the coverage a warp adds, written as A
    True
    """
    from lenslab.io.alpha import alpha_last

    try:
        return is_alpha_name(output_channels(meta, count)[-1])
    except FormatError:  # no names for this many channels
        return alpha_last(count)


def output_channels(meta: dict, count: int) -> list[str]:
    """The channel names to write for an image of ``count`` channels made from an input described by
    ``meta`` (what :func:`read` gave): the input's own names when the image has as many channels; those
    names and ``A`` when the image has one more (the coverage a warp adds to an image without alpha);
    else the usual ``Y``, ``Y A``, ``R G B``, ``R G B A``.

    >>> output_channels({"channel_names": ["u", "v"]}, 2), output_channels({"channels": ["Z"]}, 2)
    (['u', 'v'], ['Z', 'A'])
    """
    names = (meta or {}).get("channel_names") or (meta or {}).get("channels")
    ok = isinstance(names, (list, tuple)) and names and all(isinstance(n, str) and n for n in names) \
        and len(set(names)) == len(names)
    if ok and len(names) == count:
        return list(names)
    if ok and len(names) + 1 == count and not any(is_alpha_name(n) for n in names):
        return [*names, "A"]
    default = DEFAULT_CHANNELS.get(count)
    if default is None:
        raise FormatError(f"an image with {count} channels needs channel names")
    return list(default)


def fit_channels(a: "np.ndarray", fmt) -> "np.ndarray":
    """Fit an H x W x C image to what ``fmt`` (a :class:`lenslab.io.plugin.Format`) holds.

    A format without alpha drops it (RGBA -> RGB, grey+alpha -> grey); grey goes into a format whose
    files hold colour only (RGBE, PPM, video) as equal R, G and B; any other mismatch is a FormatError
    that says what the format holds.
    """
    import numpy as np

    c = a.shape[2]
    if c in fmt.channels:
        return a
    if not fmt.alpha and c in (2, 4) and c - 1 in fmt.channels:
        return a[..., :c - 1]
    if c in (1, 2) and 1 not in fmt.channels and 3 in fmt.channels:
        grey = np.repeat(a[..., :1], 3, axis=2)
        return np.concatenate([grey, a[..., 1:]], axis=2) if c == 2 and 4 in fmt.channels else grey
    holds = " or ".join(str(n) for n in fmt.channels)
    hint = {"pgm": ": write PPM, or keep one channel"}.get(fmt.name, "")
    raise FormatError(f"{fmt.title} holds {holds} channel(s); this image has {c}{hint}")


def write(path: str | os.PathLike, array: ArrayLike, format: str | None = None, *, alpha: ArrayLike | None = None,
          overwrite: bool = True, camera: Camera | None = None, **options: Any) -> Path:
    """Write an image, whole or not at all (a temporary name, then a rename).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its extension names the format unless ``format`` does.
    array : array_like
        ``H x W x C`` (or ``H x W``) linear values, ``C`` in 1, 2, 3, 4; a last channel beyond grey or RGB
        is alpha, with the colour premultiplied by it.
    format : str, optional
        A format name of ``lenslab info --formats`` (``exr``, ``hdr``, ``tiff``, ``pfm``, ``ppm``, ``jpg``,
        ``png``...), when the extension does not say it.
    alpha : array_like, optional
        ``H x W`` coverage to store as the last channel (the ``alpha`` that :func:`lenslab.warp.warp`
        returns beside its premultiplied colour). Formats without alpha (PPM, PFM, JPG, HDR) drop it.
    overwrite : bool
        False refuses to replace an existing file.
    camera : lenslab.lenses.Camera, optional
        Stored in an EXR's header (the ``lenslab.camera`` attribute), so that the file can be warped
        again without naming its lens. Other formats refuse it.
    **options
        Format options: LDR ``raw``, ``dither``, ``bits``, ``ascii``, ``quality``, ``subsampling``,
        ``compression``; PFM ``byte_order``, ``scale``; EXR ``pixel_type``, ``compression``,
        ``channels``, ``attributes`` (the module's description lists them with their defaults).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    lenslab.errors.FormatError
        An array the format cannot hold, an unknown option, or an alpha of another size.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np, lenslab
    >>> tmp = pathlib.Path(tempfile.mkdtemp())
    >>> colour = np.ones((4, 4, 3), np.float32) * 0.25
    >>> coverage = np.full((4, 4), 0.5, np.float32)
    >>> path = lenslab.write(tmp / "view.exr", colour, alpha=coverage)
    >>> lenslab.read(path)[0].shape
    (4, 4, 4)
    """
    target = Path(path)
    fmt = get(format_for_path(target, format))
    named = "channels" in options and "channels" in fmt.write_options
    import numpy as np

    image = np.asarray(array, np.float32) if named else _as_image(array)
    if image.ndim == 2:
        image = image[..., None]
    if alpha is not None:
        image = with_alpha(image, alpha)
    if fmt.name == "ppm" and image.shape[2] in (1, 2) and target.suffix.lower() != ".ppm":
        fmt = get("pgm")  # grey to .pnm: a PGM
    if not named:
        image = fit_channels(image, fmt)
    extra = set(options) - set(fmt.write_options)
    if extra:
        raise FormatError(f"unknown option(s) for {fmt.title}: {', '.join(sorted(extra))}; allowed: "
                          f"{', '.join(sorted(fmt.write_options))}")
    if camera is not None:
        if not fmt.camera:
            raise FormatError(f"{fmt.title} cannot store a camera; write EXR to keep the lens model with the image")
        options["camera"] = camera
    with atomic_write_path(target, overwrite=overwrite) as tmp:
        fmt.write(tmp, image, **options)
    return target
