"""The tone-map job: one file read, tone-mapped (or display-transformed) and written, as ``lenslab tonemap``
does it for each input, here or on a cluster worker."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from lenslab.jobs.job import Job


TONE_DROPS = ("a tone-mapped image holds display colour and alpha only (keep depth, normals and vectors "
              "with lenslab convert --to exr)")


@dataclass(frozen=True)
class TonemapJob(Job):
    """What ``lenslab tonemap`` does to each file: exposure, the curve (``curve``, ``params``, ``mode``,
    ``primaries``) or a display transform, then the output's integer depth and dither."""

    command: ClassVar[str] = "tonemap"
    verb: ClassVar[str] = "tone-mapped"
    paths: ClassVar[tuple[str, ...]] = ("ocio",)

    curve: str = "hable"
    params: dict = field(default_factory=dict)
    exposure: float | str = 0.0
    mode: str = "per-channel"
    primaries: str | None = None
    dither: bool = True
    bits: int | None = None
    display: str | None = None
    view: str | None = None
    colorspace: str | None = None
    ocio: str | None = None

    @property
    def look(self):
        from lenslab.jobs.stages import Look

        return Look(tone=self.curve, exposure=self.exposure, mode=self.mode, params=dict(self.params),
                    primaries=self.primaries, display=self.display, view=self.view, colorspace=self.colorspace,
                    ocio=self.ocio, bits=self.bits, always=True)

    def run(self, src: str, dst: str, progress=None) -> None:
        from lenslab import io
        from lenslab.jobs.policy import check_output
        from lenslab.jobs.stages import check_image

        check_output(dst, [io.split_selector(src)[0]], self.overwrite)
        image, meta = io.read(src)
        self.write(dst, check_image(image, src), meta, source=src)

    def write(self, dst: str, image, meta: dict, in_place: bool = True, source: str | None = None) -> None:
        """Develop ``image`` (scene-linear, read with ``meta``) and write it to ``dst``. ``in_place``: the
        image is given up (the curve may write in its memory; its shape stays). ``source``: the input as the
        user named it (``Trunks.exr:left``), for the notes (default: the file read)."""
        from lenslab import io
        from lenslab.io.registry import format_for_path, get
        from lenslab.jobs.stages import check_data_channels, develop, encode_options

        where = source or meta.get("path", "the image")
        if "lenslab:stmap" in (meta.get("attributes") or {}):
            from lenslab.errors import InputError

            raise InputError(f"{where}: is an ST map (its header's lenslab:stmap mark): its values are source "
                             "positions, never tone-mapped; apply it with 'lenslab warp IMAGE --stmap MAP', or write "
                             "it as codes with 'lenslab convert MAP -o map.png'")
        check_data_channels(where, meta, image.shape[-1] if image.ndim == 3 else 1)
        fmt = get(format_for_path(dst, None))
        from lenslab.io.exr.extra import warn_dropped

        warn_dropped(where, meta.get("extra_channels") or [], fmt.title, TONE_DROPS)
        from dataclasses import replace

        from lenslab.jobs.primaries import applied_primaries

        look = replace(self.look, primaries=applied_primaries(self.primaries, meta))  # sRGB's for a tagged file
        out, shown = develop(image, meta, fmt, look, in_place=in_place)
        dither = None if self.display else self.dither  # display code values are rounded, never dithered
        opts = encode_options(fmt, {"camera": meta.get("camera")}, {"bits": self.bits, "dither": dither},
                              channels=out.shape[-1])
        if source or meta.get("path"):  # the photo's camera tags, where the format keeps them (the same frame)
            from lenslab.io.exif import carried

            opts.update(carried(io.split_selector(source or meta["path"])[0], meta, out.shape[1::-1], fmt))
        if in_place and "in_place" in fmt.write_options:  # (out is the image given up, or develop's own)
            opts["in_place"] = True
        io.write(dst, out, overwrite=self.overwrite, **{**opts, **shown})


def write_tone_mapped(path, image, dither=True, bits=None, overwrite=True, camera=None) -> None:
    """Write display-linear values: display formats encode to sRGB and quantise; float formats keep them."""
    from lenslab import io
    from lenslab.io.registry import format_for_path, get
    from lenslab.jobs.stages import encode_options

    fmt = get(format_for_path(path, None))
    opts = encode_options(fmt, {}, {"bits": bits, "dither": dither}, camera=camera, channels=image.shape[-1])
    io.write(path, image, overwrite=overwrite, **opts)


__all__ = ["TonemapJob", "write_tone_mapped"]
