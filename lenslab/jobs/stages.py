"""The stages every job shares, each written once: the look (exposure, then a tone curve or an OpenColorIO
display transform), the encode stage (the write options a format declares, filled from the job's options
and what the input held), and the image-shape check.

The encode stage asks the target format's record (:class:`lenslab.io.plugin.Format`) what it can hold:
alpha, bit depths, a camera header, its write options. It never tests a format's name.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from lenslab.io.alpha import alpha_last, expose, has_alpha  # noqa: F401  (the look's exposure: colour, never alpha)


class DisplaySourceWarning(UserWarning):
    """``lenslab tonemap`` (a look applied ``always``) given a display image (an 8-bit JPG or PNG, an SDR clip):
    the curve maps scene light to the display, and applied to display values it changes the picture (hable
    darkens it)."""


@dataclass(frozen=True)
class Look:
    """How scene-linear values become what a display file stores.

    ``exposure``: stops (a number) or ``"auto"``; ``tone``, ``mode``, ``params``, ``primaries``: the tone
    curve (:func:`lenslab.tone.tonemap`); ``display``, ``view``, ``colorspace``, ``ocio``: an OpenColorIO
    display transform instead of the curve; ``bits``: the integer depth asked of the output (``--bits``);
    ``always``: apply the curve whatever the output (``lenslab tonemap``: float outputs keep
    display-linear values), else only for display outputs of scene-linear input."""

    tone: str = "hable"
    exposure: float | str = 0.0
    mode: str = "per-channel"
    params: dict = field(default_factory=dict)
    primaries: str = "sRGB"
    display: str | None = None
    view: str | None = None
    colorspace: str | None = None
    ocio: str | None = None
    bits: int | None = None
    always: bool = False
    tone_given: bool = False  # the user typed the curve: said when a display source does not take it

    def display_options(self) -> dict:
        return {"display": self.display, "view": self.view, "colorspace": self.colorspace, "ocio": self.ocio,
                "bits": self.bits}


def develop(image, meta: dict, fmt, look: Look, in_place: bool = False, of: str | None = None) -> tuple:
    """(image as format record ``fmt`` stores it, write options the look needs): the display transform,
    else the tone curve where the output holds display values, else the exposure alone; for display values
    the colours of a wide-gamut file outside Rec.709's gamut are clipped first, with a note that counts them
    (:func:`lenslab.io.colour.gamut.clip_outside`), and so they are for a float format that cannot hold them
    (Radiance RGBE); ``of`` names what ``image`` is when not the file's own pixels (``the warped image
    out.png``), for that note. Alpha (the last channel of 2 or 4) passes through.
    ``in_place``: the caller gives ``image`` up, and an exposure alone (or a tone curve) is applied in its
    memory. Raises :class:`~lenslab.errors.FormatError` for a look the output cannot hold."""
    from lenslab.errors import FormatError

    exposure = look.exposure
    from lenslab.io import carries_alpha

    alpha = carries_alpha(meta, image.shape[2]) if getattr(image, "ndim", 0) == 3 else False
    integers = bool(look.bits) and "sample_type" in fmt.write_options  # TIFF with --bits: display-encoded
    if look.display:
        from lenslab.jobs.display import apply_display

        if exposure == "auto":
            raise FormatError("--exposure auto goes with a tone curve; give a number of stops with --display")
        # (a format that holds scene-linear light is refused there, before the transform)
        return apply_display(expose(image, exposure, alpha=alpha), fmt, {**look.display_options(), "alpha": alpha})
    if look.always or not fmt.hdr or integers or fmt.clips_negatives:  # display values (or RGBE's): a wide-gamut
        from lenslab.io.colour.gamut import clip_outside  # file's colours outside Rec.709's gamut are clipped here

        clipped = clip_outside(image, meta, alpha, in_place=in_place, of=of)
        in_place, image = in_place or clipped is not image, clipped  # a clipped copy is the curve's to work in
    if look.always or ((not fmt.hdr or integers) and (not meta.get("display_encoded") or exposure == "auto")):
        from lenslab.tone import tonemap

        if look.always and meta.get("display_encoded") and look.tone != "clamp":  # (tonemap of a JPG, a PNG)
            import warnings

            note = (f"holds display values already (an SDR image): the {look.tone} curve, made for scene light, "
                    "maps them a second time and changes its brightness and contrast ('lenslab convert' re-encodes it "
                    "without a curve; --tone clamp keeps its values)")
            warning = DisplaySourceWarning(f"{meta.get('path', of or 'the image')}: {note}")
            warning.command_line = note  # (a batch names the file itself)
            warnings.warn(warning, stacklevel=2)

        if exposure == "auto" and meta.get("format") != "video":  # the stops found, said as tonemap says them
            exposure = _said_auto_exposure(image, meta, look, alpha, of)
        return tonemap(image, curve=look.tone, exposure=exposure, mode=look.mode, primaries=look.primaries,
                       in_place=in_place, alpha_channel=alpha, **dict(look.params)), {}
    if look.tone_given and (not fmt.hdr or integers) and meta.get("display_encoded"):
        import warnings

        from lenslab.jobs.funnel import CommandNote

        warnings.warn(CommandNote(f"--tone {look.tone} not applied: the source holds display values already (a "
                                  "tone curve maps HDR scene light; --exposure still applies)"), stacklevel=2)
    if exposure == "auto":
        from lenslab.io.registry import formats

        shown = ", ".join(f.name for f in formats().values() if f.writable and not f.hdr and f.kind == "image")
        raise FormatError(f"--exposure auto applies when writing display formats ({shown})")
    exposed = expose(image, exposure, in_place=in_place, alpha=alpha)
    if fmt.clips_negatives and getattr(exposed, "ndim", 0) == 3:  # the file's own negatives, said as a display
        from lenslab.tone.mapping import warn_negatives  # output says them (RGBE sets them to 0)

        warn_negatives(exposed[..., :-1] if alpha else exposed, f"{fmt.title} holds no negative values:")
    return exposed, {}


class AutoExposureNote(UserWarning):
    """The stops ``--exposure auto`` found for one image (convert, warp), so that a batch can be repeated, or a
    clip's frames given one exposure, with ``--exposure`` set to them. ``command_line``: without the path."""


def _said_auto_exposure(image, meta: dict, look, alpha: bool, of: str | None) -> float:
    import warnings

    from lenslab.tone import auto_exposure

    ev = auto_exposure(image, primaries=look.primaries, alpha_channel=alpha)
    note = f"auto exposure {ev:+.2f} stops"
    warning = AutoExposureNote(f"{meta.get('path', of or 'the image')}: {note}")
    warning.command_line = note
    warnings.warn(warning, stacklevel=3)
    return ev


def resolved_exposure(image, exposure, primaries=None, where: str = "", quiet: bool = False,
                      alpha: bool | None = None):
    """``exposure`` with ``"auto"`` worked out from ``image`` once (:func:`lenslab.tone.auto_exposure`) and
    said on standard error, so that a command shows the stops it used; a number is returned as it is."""
    if str(exposure).strip().lower() != "auto":
        return exposure
    import sys

    from lenslab.tone import auto_exposure

    ev = auto_exposure(image, primaries=primaries, alpha_channel=alpha)
    if not quiet:
        print(f"{where}: auto exposure {ev:+.2f} stops", file=sys.stderr)
    return ev


def encode_options(fmt, meta: dict, options: dict, camera=None, channels: int | None = None) -> dict:
    """The write options of format record ``fmt``, from the job's ``options`` and what the input held
    (``meta``): only what the format declares it accepts.

    ``options``: ``quality``, ``bits``, ``dither``, ``pixel_type`` (EXR-style float type; None: each channel's
    stored type when the input is of the same format, else half), ``sample_type`` (TIFF-style), ``compression`` (None: the
    format's default). ``camera``: stored where the format can hold one (default: the input's)."""
    opts: dict = {}
    accepts = fmt.write_options
    bits = options.get("bits")
    if "quality" in accepts and options.get("quality") is not None:
        opts["quality"] = options["quality"]
    if "bits" in accepts and bits:
        opts["bits"] = bits
    if "sample_type" in accepts:
        opts["sample_type"] = f"uint{bits}" if bits else (options.get("sample_type") or "float")
    if "pixel_type" in accepts:
        pixel_type = options.get("pixel_type")
        stored = meta.get("channel_types") if meta.get("format") == fmt.name else None
        if pixel_type is None and stored and len(stored) == channels and set(stored) <= {"half", "float", "uint"}:
            pixel_type = list(stored)  # each channel as the input stored it (R, G, B, A half beside a float Z)
        elif pixel_type is None:
            kept = meta.get("sample_type") if meta.get("format") == fmt.name else "half"
            pixel_type = kept if kept in ("half", "float") else "float"
        opts["pixel_type"] = pixel_type
    if "dither" in accepts and options.get("dither") is not None and (not fmt.hdr or bits):
        opts["dither"] = options["dither"]  # (quantising to integers only)
    if "compression" in accepts and options.get("compression") is not None:
        opts["compression"] = options["compression"]
    if channels and "channels" in accepts:  # the input's channel names where kept, else Y A / R G B A
        from lenslab.io import output_channels

        opts["channels"] = output_channels(meta, channels)
    camera = meta.get("camera") if camera is None else camera
    if fmt.camera and camera is not None:
        opts["camera"] = camera
    return opts


def keeps_alpha(fmt, wanted: bool = True) -> bool:
    """Whether an output of format ``fmt`` carries alpha: its record says it holds alpha (whatever the
    format) and the job wants it. The record's ``straight_alpha`` says whether the file keeps straight or
    premultiplied colour; its plugin converts at the boundary (:mod:`lenslab.io.alpha`)."""
    return bool(wanted and fmt.alpha)


def check_image(image, what: str = "image"):
    """An image as every stage takes it: a float32 H x W x C array, C in {1, 2, 3, 4}, H and W at least 1.
    A 2-D array is taken as one channel. Raises :class:`~lenslab.errors.FormatError` naming ``what``."""
    import numpy as np

    from lenslab.errors import check_image_shape

    a = check_image_shape(image, str(what))
    return (a[..., None] if a.ndim == 2 else a).astype(np.float32, copy=False)


__all__ = ["Look", "develop", "encode_options", "expose", "has_alpha", "keeps_alpha", "check_image",
           "check_data_channels"]


def known_channels(src) -> int | None:
    """How many channels reading ``src`` gives, when its header tells without reading pixels: a format whose
    images all have one count (PPM, Radiance HDR, PGM), or a file whose header names R, G, B (and A) only
    (the format record's ``channel_names``: an EXR's first part); None when only reading it would tell (a
    part or layer selector, other layers, other formats)."""
    from lenslab.io import split_selector
    from lenslab.io.registry import get, sniff

    file, selector = split_selector(src)
    try:
        fmt = get(sniff(file))
        if len(fmt.channels) == 1:
            return fmt.channels[0]
        if fmt.channel_names is not None and selector is None:  # the header's list, no pixel decoded
            names = set(fmt.channel_names(file))
            if names in ({"R", "G", "B"}, {"R", "G", "B", "A"}):
                return len(names)
    except Exception:  # noqa: BLE001 - a file its header does not describe: reading it reports why
        return None
    return None


def check_channels_fit(src, fmt) -> None:
    """A usage error, before any work, when the output format record ``fmt`` cannot hold the channels of
    ``src`` as its header tells them (an RGB image to PGM); the rule and words of
    :func:`lenslab.io.fit_channels`, which writing applies."""
    channels = known_channels(src)
    if channels is None:
        return
    import numpy as np

    from lenslab.errors import FormatError, UsageError
    from lenslab.io import fit_channels

    try:
        fit_channels(np.zeros((1, 1, channels), np.float32), fmt)
    except FormatError as exc:
        raise UsageError(f"{src}: {exc}") from None


def check_data_channels(src, meta: dict, count: int, fmt=None) -> None:
    """:class:`~lenslab.errors.FormatError` (one line naming ``src``) when an image of 2 or 4 channels carries
    no alpha (its names say so: ``u, v``; ``R, G, B, Z``; only ``A`` is alpha) and would go where the last
    of 2 or 4 channels is taken for alpha or dropped: a format record ``fmt`` that does not keep channel
    names (only EXR does), or a tone curve (``fmt`` None), which acts on colour and alpha."""
    if count not in (2, 4):
        return
    from lenslab.errors import FormatError
    from lenslab.io import carries_alpha, output_channels

    if carries_alpha(meta, count) or (fmt is not None and "channels" in fmt.write_options):
        return
    names = ", ".join(output_channels(meta, count))
    where = (f"{fmt.title} would take the last for alpha or drop it: write EXR, which keeps them by name"
             if fmt is not None else "a tone curve acts on colour and alpha: keep them with lenslab convert --to exr")
    raise FormatError(f"{src}: channels {names} hold data, none is alpha (only A is); {where}")

