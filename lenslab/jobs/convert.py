"""The convert job: one file of ``lenslab convert`` read, developed for the target format, written; a clip
becomes one file per frame (:mod:`lenslab.jobs.convert_video`)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

from lenslab.jobs.job import Job


@dataclass(frozen=True)
class ConvertJob(Job):
    """What ``lenslab convert`` does to each file: the target format ``to``, the look for display
    outputs (tone curve or display transform, exposure) and the format's write options."""

    command: ClassVar[str] = "convert"
    verb: ClassVar[str] = "converted"
    paths: ClassVar[tuple[str, ...]] = ("ocio",)

    to: str = "exr"
    tone: str = "hable"
    tone_given: bool = False
    exposure: float | str = 0.0
    quality: int | None = 95
    bits: int | None = None
    pixel_type: str | None = None
    compression: str | None = None
    data_window: bool = False
    frames: tuple | None = None
    display: str | None = None
    view: str | None = None
    colorspace: str | None = None
    ocio: str | None = None
    quiet: bool = False

    @property
    def look(self):
        from lenslab.jobs.stages import Look

        return Look(tone=self.tone, tone_given=self.tone_given, exposure=self.exposure, display=self.display, view=self.view,
                    colorspace=self.colorspace, ocio=self.ocio, bits=self.bits)

    @property
    def encoding(self) -> dict:
        """The encode stage's options (``--pixel-type`` is the float type of EXR and TIFF alike)."""
        return {"quality": self.quality, "bits": self.bits, "pixel_type": self.pixel_type,
                "sample_type": self.pixel_type, "compression": self.compression}

    def develop(self, image, meta: dict, in_place: bool = False):
        """(image as the target format stores it, write options); ``in_place``: ``image`` may be changed."""
        from lenslab.io.registry import get
        from lenslab.jobs.stages import develop, encode_options

        fmt = get(self.to)
        job = self if self.bits else replace(self, bits=kept_bits(fmt, meta))
        image, shown = develop(image, meta, fmt, job.look, in_place=in_place)
        return image, {**encode_options(fmt, meta, job.encoding, channels=image.shape[-1]), **shown}

    def run(self, src: str, dst: str, progress=None) -> None:
        from lenslab.io import read, split_selector, write
        from lenslab.jobs.policy import check_output
        from lenslab.jobs.stages import check_image
        from lenslab.jobs.warp.video import is_video

        src_file, _ = split_selector(src)
        check_output(dst, [src_file], self.overwrite)
        if is_video(src_file):  # a clip: one file per frame
            from lenslab.jobs.convert_video import frames_to_files

            frames_to_files(str(src_file), dst, self)
            return
        from lenslab.io.registry import get

        fmt = get(self.to)
        keeps_extra = "extra" in fmt.write_options  # depth, normals...: kept where the output holds them
        from lenslab.io.registry import sniff

        same = fmt.name == "exr" and sniff(src_file) == "exr"  # EXR to EXR: the data window stays as stored
        image, meta = read(src, data_window=self.data_window or same, extra_channels=keeps_extra)
        if hasattr(progress, "status"):  # the steps after the reading, named should one outlast the patience
            progress.status("converting")
        from lenslab.jobs.stages import check_data_channels

        check_data_channels(src, meta, image.shape[-1] if image.ndim == 3 else 1, fmt)
        if meta.get("other_views"):  # one view of a multi-view EXR: written alone, as a plain image
            from lenslab.io.exr.extra import warn_dropped

            rest = [v for v in (meta["attributes"].get("multiView") or []) if v != meta["view"]]
            warn_dropped(src, meta["other_views"], fmt.title, f"they belong to the other view(s) {', '.join(rest)}; "
                                                              f"view {meta['view']} is written alone, as a plain image")
        # the image read is this job's own: the exposure and the writer's narrowing reuse its memory
        codes = map_codes(fmt, meta, self.bits)
        if "lenslab:stmap" in (meta.get("attributes") or {}):  # coordinates, not colours: no look applies
            refuse_look_of_map(src, self, codes is not None)
        notes = map_notes(fmt, meta, image, codes)  # an ST map's precision and validity lost: one note
        if notes:
            import warnings

            warnings.warn("; ".join(notes), UserWarning, stacklevel=2)
        if codes is not None:  # an ST map holds coordinates, not colours: written as raw codes
            image, write_opts = check_image(image, src), codes
        else:
            image, write_opts = self.develop(check_image(image, src), meta, in_place=True)
        if "in_place" in fmt.write_options:
            write_opts["in_place"] = True
        if keeps_extra and meta.get("extra_planes"):
            from lenslab.io.exr.extra import clashing, warn_dropped

            lost = clashing(list(meta["extra_planes"]), write_opts.get("channels") or [])
            write_opts["extra"] = {n: p for n, p in meta["extra_planes"].items() if n not in lost}
            warn_dropped(src, lost, fmt.title, "the layer's own channels are written under those names (convert "
                                               "the file without a layer to keep every channel)")
        if same:  # the windows and the header attributes that still hold (lenslab.io.exr.keep)
            from lenslab.io.exr.keep import kept_header, warn_scanlines

            warn_scanlines(src, meta)  # tiles and smaller levels are not kept: said in one note

            written = [*write_opts.get("channels", meta["channels"]), *write_opts.get("extra", {})]
            write_opts.update(kept_header(meta, written))
        else:
            from lenslab.io.exr.extra import warn_dropped

            warn_dropped(src, meta.get("extra_channels") or [], fmt.title)
        write_opts.update(carried_exif(src_file, meta, image, fmt, same))  # the photo's camera tags, if kept
        if hasattr(progress, "status"):
            from pathlib import Path

            progress.status(f"writing {Path(dst).name}")  # (encoding a large PNG takes seconds)
        write(dst, image, format=self.to, overwrite=self.overwrite, **write_opts)


def carried_exif(path, meta: dict, image, fmt, same: bool) -> dict:
    """The write option that carries the camera EXIF of the photo at ``path`` (:mod:`lenslab.io.exif`) to ``image``
    written in format record ``fmt``: the image as read is the photo's whole frame, unless it is an EXR's data window
    read alone (``--data-window``; EXR to EXR (``same``) keeps the display window, so the frame)."""
    from lenslab.io.exif import carried

    h, w = image.shape[:2]
    window = meta.get("display_window")
    full = (window[2] - window[0] + 1, window[3] - window[1] + 1) if window is not None else (w, h)
    return carried(path, meta, full if same else (w, h), fmt, full=full)


def map_codes(fmt, meta: dict, bits: int | None) -> dict | None:
    """The write options of an ST map (an EXR whose header holds ``lenslab:stmap``, as ``lenslab stmap``
    writes it) going to integer samples (PNG, PPM, JPG; TIFF with ``bits``): its s, t and A as raw codes over
    their maximum (16-bit unless ``bits`` says 8, where the format holds 16), neither tone-mapped nor
    sRGB-encoded, the way OpenCV, tifffile and Nuke (colourspace raw) store maps and
    :func:`lenslab.stmap.read_st_map` reads them; None for any other image, or a float output."""
    if "lenslab:stmap" not in (meta.get("attributes") or {}) or "raw" not in fmt.write_options:
        return None
    if fmt.hdr and not bits:  # a float TIFF: the values as they are
        return None
    bits = bits or (16 if 16 in fmt.bit_depths else 8)
    if "sample_type" in fmt.write_options:
        return {"raw": True, "sample_type": f"uint{bits}"}
    return {"raw": True, **({"bits": bits} if "bits" in fmt.write_options else {})}


def check_maps_look(files, to: str, bits: int | None, job) -> None:
    """Before a batch: :func:`refuse_look_of_map` for every EXR among ``files`` whose header carries the
    ``lenslab:stmap`` mark, whatever format ``to`` writes it in, where ``job`` (a :class:`ConvertJob`'s look fields)
    names a look; only the headers are read, and only when a look option was given."""
    from lenslab.io.registry import get

    fmt = get(to)
    codes = "raw" in fmt.write_options and not (fmt.hdr and not bits)  # (as :func:`map_codes` writes it)
    if not (job.tone_given or job.exposure not in (0, 0.0) or job.display):
        return
    from lenslab.io import split_selector
    from lenslab.io.registry import sniff

    for f in files:
        path = split_selector(str(f))[0]
        try:
            if sniff(path) != "exr":
                continue
            import OpenEXR

            marked = "lenslab:stmap" in OpenEXR.File(str(path), header_only=True).parts[0].header
        except Exception:  # a file that cannot be read: its own error comes when it is converted
            continue
        if marked:
            refuse_look_of_map(str(f), job, codes)


def refuse_look_of_map(src: str, job: ConvertJob, codes: bool = True) -> None:
    """A :class:`~lenslab.errors.UsageError` naming the look options given (``--tone``, ``--exposure``, ``--display``
    and its ``--view``/``--colorspace``) for an ST map, written as codes (``codes``, :func:`map_codes`) or as floats:
    its values are source positions, never tone-mapped, exposed nor display-encoded (an exposure of a float map
    would move every position and keep the mark)."""
    from lenslab.errors import UsageError

    given = [flag for flag, on in (("--tone", job.tone_given), ("--exposure", job.exposure not in (0, 0.0)),
                                   ("--display", job.display), ("--view", job.view),
                                   ("--colorspace", job.colorspace)) if on]
    if given:
        how = "written as raw codes" if codes else "not colours"
        raise UsageError(f"{src}: is an ST map (its header's lenslab:stmap mark): its values are source positions, "
                         f"{how}, never tone-mapped or display-encoded; drop {', '.join(given)}")


def map_notes(fmt, meta: dict, image, codes: dict | None) -> list[str]:
    """What an ST map (an EXR whose header holds ``lenslab:stmap``) loses in format ``fmt``, said in one note: written
    as 8-bit codes (``codes``: JPG, or ``--bits 8``), each source position kept only to 1/255 of the source's size
    (the width the header records), a JPG's lossy coding moving it further; in a format without alpha (PPM, PFM,
    Radiance HDR, JPG), its A (which pixels see the source), each pixel that sees nothing (s = t = 0 there) then read
    as the source's bottom-left corner, as a map without A is (:func:`lenslab.stmap.read_st_map`)."""
    if "lenslab:stmap" not in (meta.get("attributes") or {}):
        return []
    notes = []
    if codes is not None and (codes.get("bits") == 8 or codes.get("sample_type") == "uint8"
                              or 16 not in fmt.bit_depths):
        from lenslab.stmap_frame import recorded_source

        found = (recorded_source(meta) or (None, None))[1]
        pixels = f"{found[0] / 255:.2g}" if found else ""
        step = f" ({pixels} pixel{'' if pixels == '1' else 's'} of its {found[0]}-pixel width)" if found else ""
        lossy = ", and JPG's lossy coding moves them further" if fmt.name == "jpg" else ""
        notes.append(f"an ST map at 8 bits places each source position only to 1/255 of the source's size{step}"
                     f"{lossy}; PNG or TIFF at 16 bits keep 1/65535, EXR the values themselves")
    blind = int((image[..., 3] <= 0.5).sum()) if image.ndim == 3 and image.shape[2] == 4 and not fmt.alpha else 0
    if blind:
        total = image.shape[0] * image.shape[1]
        notes.append(f"{fmt.title} keeps no alpha: the ST map's A channel (which pixels see the source) is dropped, "
                     f"and its {blind} of {total} pixels that see nothing ({100 * blind / total:.3g}%) would read the "
                     "source's bottom-left corner when the map is applied; PNG, TIFF or EXR keep A")
    return notes


def kept_bits(fmt, meta: dict) -> int | None:
    """16 where the input holds integers of 9 to 16 bits (a 16-bit PNG, a 10- or 12-bit HEIC) and format record
    ``fmt`` writes 16-bit integers (PNG, PPM/PGM, TIFF): the input's precision is kept, as EXR to EXR keeps its
    pixel type; else None (the format's default). ``--bits`` overrides it."""
    integers = {"bits", "sample_type"} & set(fmt.write_options)
    deep = 8 < (meta.get("bit_depth") or 8) <= 16
    if meta.get("sample_type") == "uint" and deep and 16 in fmt.bit_depths and integers:
        return 16
    return None


__all__ = ["ConvertJob", "kept_bits", "map_codes"]
