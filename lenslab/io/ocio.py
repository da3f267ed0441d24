"""OpenColorIO display transforms: scene-linear pixels -> a display's code values through a config's view.

The config is ``ocio://default`` (the built-in CG config shipped with the ``opencolorio`` wheel: sRGB,
Display P3, Rec.1886, Rec.2100-PQ displays; ACES 2.0 SDR/HDR, Un-tone-mapped and Video views), any
other built-in (``ocio://studio-config-latest`` adds Rec.2100-HLG), or a studio's config file. The
input colour space defaults to linear Rec.709 (lenslab reads every file into Rec.709 primaries; an
EXR's own chromaticities are converted on reading) and may be any colour space of the config.

Names may be given in full (``"sRGB - Display"``, ``"ACES 2.0 - SDR 100 nits (Rec.709)"``), or by
any unique case-insensitive part (``srgb``, ``rec.2100-pq``, ``"sdr 100 nits (rec.709)"``). A
name that matches nothing or several is an error listing the valid ones.

The transform is OpenColorIO's own CPU processor (float32, in place on a copy); alpha passes through
unchanged. The result is display-encoded: files store it as code values without lenslab's sRGB
encoding (``raw=True``).
"""

from __future__ import annotations

import functools

import numpy as np

from lenslab.errors import FormatError, cause

DEFAULT_CONFIG = "ocio://default"
DEFAULT_COLORSPACE = "lin_rec709"


class OCIOError(FormatError):
    """An OpenColorIO config, display, view or colour space cannot be used as asked."""


def _ocio():
    try:
        import PyOpenColorIO
    except ImportError:
        raise OCIOError("display transforms need OpenColorIO: pip install 'lenslab[ocio]'") from None
    return PyOpenColorIO


@functools.lru_cache(maxsize=4)
def load_config(source: str | None = None):
    """An OpenColorIO config from a file or an ``ocio://`` name (default: ``ocio://default``)."""
    ocio = _ocio()
    if source and not str(source).startswith("ocio://"):  # a file: regular and bounded, never a device
        from lenslab.inputs.sidefile import check_side_file

        check_side_file(source, "OCIO config", 16 << 20)
    try:
        config = ocio.Config.CreateFromFile(str(source or DEFAULT_CONFIG))
    except Exception as exc:
        raise OCIOError(f"cannot load the OpenColorIO config {source or DEFAULT_CONFIG!r} ({cause(exc)})") from None
    if source and not str(source).startswith("ocio://"):
        check_lut_files(config, source)
    return config


def _file_sources(transform):
    """The ``src`` of every FileTransform in ``transform`` (GroupTransforms walked)."""
    ocio = _ocio()
    if isinstance(transform, ocio.FileTransform):
        yield transform.getSrc()
    elif isinstance(transform, ocio.GroupTransform):
        for inner in transform:
            yield from _file_sources(inner)


def check_lut_files(config, source) -> None:
    """Every LUT file the config's transforms name (colour spaces, view transforms, looks, named
    transforms), where it resolves to a file, is a regular file within the side-file limit
    (:mod:`lenslab.inputs.sidefile`), before OpenColorIO reads any: it would read ``/dev/zero`` without
    end, wait on a FIFO for ever and load a file of any size. A name that resolves to nothing is left to
    OpenColorIO, which says so if a transform needs it."""
    ocio = _ocio()
    from lenslab.inputs.sidefile import check_side_file

    transforms = []
    for cs in config.getColorSpaces(ocio.SEARCH_REFERENCE_SPACE_ALL, ocio.COLORSPACE_ALL):
        transforms += [cs.getTransform(ocio.COLORSPACE_DIR_TO_REFERENCE),
                       cs.getTransform(ocio.COLORSPACE_DIR_FROM_REFERENCE)]
    for vt in config.getViewTransforms():
        transforms += [vt.getTransform(ocio.VIEWTRANSFORM_DIR_TO_REFERENCE),
                       vt.getTransform(ocio.VIEWTRANSFORM_DIR_FROM_REFERENCE)]
    for look in config.getLooks():
        transforms += [look.getTransform(), look.getInverseTransform()]
    for nt in config.getNamedTransforms(ocio.NAMEDTRANSFORM_ALL):
        transforms += [nt.getTransform(ocio.TRANSFORM_DIR_FORWARD), nt.getTransform(ocio.TRANSFORM_DIR_INVERSE)]
    context = config.getCurrentContext()
    for src in dict.fromkeys(s for t in transforms if t is not None for s in _file_sources(t)):
        try:
            path = context.resolveFileLocation(src)
        except Exception:  # noqa: BLE001 - not found on the search path: OpenColorIO's own error if used
            continue
        check_side_file(path, f"LUT file of the OCIO config {source}")


def _pick(kind: str, name: str, choices: list[str]) -> str:
    """The one of ``choices`` that ``name`` means (case aside): the same name, else the one whose name before
    " - " it is, else the one name that holds it; :class:`OCIOError` when none or several do."""
    low = name.strip().lower()
    if not low:  # an empty name would hold in every name: refuse it rather than fall back to a default
        raise OCIOError(f"{kind}: the name is empty; the config's are: {'; '.join(choices)}")
    for c in choices:
        if c.lower() == low:
            return c
    # the name before " - " ("Display P3" of "Display P3 - Display") wins over longer names holding it
    found = [c for c in choices if c.lower().partition(" - ")[0].strip() == low]
    if len(found) != 1:
        found = [c for c in choices if low in c.lower()]
    if len(found) == 1:
        return found[0]
    which = "matches several" if found else "is not one"
    raise OCIOError(f"{kind} {name!r} {which} of the config's: {'; '.join(found or choices)}")


def resolve(config, display: str, view: str | None, colorspace: str | None = None) -> tuple[str, str, str]:
    """(display, view, colour space) as the config names them; ``view`` None: the display's default."""
    d = _pick("display", display, list(config.getDisplays()))
    views = list(config.getViews(d))
    v = config.getDefaultView(d) if view is None else _pick(f"view of {d!r}", view, views)
    cs_name = DEFAULT_COLORSPACE if colorspace is None else colorspace
    cs = config.getCanonicalName(cs_name) or None
    if not cs:
        cs = _pick("colour space", cs_name, [c.getName() for c in config.getColorSpaces()])
    return d, v, cs


def is_hdr_display(display: str) -> bool:
    """A display whose code values cover more than SDR (PQ, HLG): needs 16-bit files or 10-bit video."""
    low = display.lower()
    return any(k in low for k in ("pq", "hlg", "st2084", "hdr"))


def processor(display: str, view: str | None = None, colorspace: str | None = None, config: str | None = None):
    """OpenColorIO's CPU processor for scene-linear ``colorspace`` -> ``display`` through ``view``."""
    ocio = _ocio()
    cfg = load_config(config)
    d, v, cs = resolve(cfg, display, view, colorspace)
    t = ocio.DisplayViewTransform(src=cs, display=d, view=v)
    try:
        return cfg.getProcessor(t).getDefaultCPUProcessor(), (d, v, cs)
    except Exception as exc:
        raise OCIOError(f"OpenColorIO cannot build the transform {cs!r} -> {d!r} / {v!r} ({cause(exc)})") from None


@functools.lru_cache(maxsize=16)
def reference_white_gain(display: str, view: str, colorspace: str, config: str | None = None) -> float:
    """The scene-linear gain that puts 1.0 on BT.2408's HDR reference white (203 cd/m², ITU-R BT.2408) in a
    PQ or HLG display's colorimetric view; 1.0 for SDR displays and tone-mapping views.

    OpenColorIO's configs scale their HDR displays so that 1.0 is 100 cd/m²: through an un-tone-mapped
    or video view a diffuse white of 1.0 would land at 100 cd/m², and a reader that decodes PQ or HLG as
    BT.2408 says (lenslab, FFmpeg's tone mapping, colour-science divided by 203) gets 0.49 of it back. A
    view is colorimetric when twice the light gives twice the display light; tone-mapping views (ACES
    output transforms) place white themselves and are left as their authors made them."""
    from lenslab.io.colour.png_cicp import display_code_points, to_linear_light

    points = display_code_points(display)
    if points is None or points[1] not in (16, 18):  # SDR (an SDR P3 display has code points too)
        return 1.0
    cpu, _ = processor(display, view, colorspace, config)
    probe = np.array([[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]], np.float32)
    cpu.applyRGB(probe)
    light, _ = to_linear_light(np.clip(probe, 0.0, 1.0), points)  # 1.0 = 203 cd/m2, as files are read
    one, two = float(light[0, 0, 1]), float(light[0, 1, 1])
    if not (one > 0.0 and abs(two / (2.0 * one) - 1.0) < 1e-3):
        return 1.0
    return 1.0 / one


def display_transform(image: np.ndarray, display: str, view: str | None = None, colorspace: str | None = None,
                      config: str | None = None, alpha_channel: bool | None = None) -> np.ndarray:
    """float32 H x W x C scene-linear -> display code values (float32, same shape; alpha unchanged).

    ``alpha_channel``: whether the last channel is alpha (what the image's channel names say: only ``A``
    is); None: 2 or 4 channels carry it (:func:`lenslab.io.alpha.alpha_last`, the rule of the warp APIs).
    The colour is one channel (grey, R = G = B, returned as one channel) or three; other channels (data
    named ``Z`` or ``u, v``) have no display colour and are refused. A PQ or HLG display's
    colorimetric view puts 1.0 at 203 cd/m² (:func:`reference_white_gain`).
    """
    from lenslab.io.alpha import alpha_last

    a = np.asarray(image, np.float32)
    c = a.shape[-1]
    alpha = a.ndim == 3 and alpha_last(c, alpha_channel)
    colour = c - 1 if alpha else c
    if colour not in (1, 3):
        raise OCIOError(f"a display transform takes grey or RGB colour (plus alpha); this image has {colour} "
                        f"colour channel{'s' if colour != 1 else ''}{' and alpha' if alpha else ''}")
    cpu, (d, v, cs) = processor(display, view, colorspace, config)
    rgb = np.repeat(a[..., :1], 3, axis=-1) if colour == 1 else a[..., :3]
    out = np.array(rgb, dtype=np.float32, order="C")  # a copy: OpenColorIO works in place
    gain = reference_white_gain(d, v, cs, config)
    if gain != 1.0:
        out *= np.float32(gain)
    cpu.applyRGB(out)
    out = np.nan_to_num(out, nan=0.0, posinf=1.0, neginf=0.0)
    if colour == 1:
        out = out[..., :1]
    if alpha:
        out = np.concatenate([out, a[..., -1:]], axis=-1)
    return out.astype(np.float32, copy=False)
