"""``--pixel-type``, the sample type of an output file, for ``lenslab warp`` and ``lenslab convert`` alike: one of the
types the output's format holds (:attr:`lenslab.io.plugin.Format.pixel_types`, from the format plugins) is written as
asked (``half`` or ``float`` samples of an EXR or TIFF, 8- or 16-bit integers of a PNG, a TIFF or a PPM); any other is
a usage error in one line naming what the format holds, never an option silently ignored."""

from __future__ import annotations


def _image_formats():
    from lenslab.io.registry import formats

    return [f for f in formats().values() if f.writable and f.kind == "image"]


def pixel_type_choices() -> tuple[str, ...]:
    """Every type some written image format holds (``half``, ``float``, ``rgbe``, ``uint8``, ``uint16``), integers
    last, for the command line's choices."""
    names = dict.fromkeys(t for f in _image_formats() for t in f.pixel_types)
    return tuple(sorted(names, key=lambda t: (t.startswith("uint"), integer_bits(t) or 0)))


def check_pixel_type(value: str | None, fmt, bits: int | None = None) -> None:
    """A :class:`~lenslab.errors.UsageError` where ``--pixel-type value`` cannot be written to format record ``fmt``:
    a type it does not hold (the line names what it holds and which formats hold ``value``), a clip (its samples are
    its codec's), or ``--bits`` asking for another depth or for integers beside a float type. None: nothing asked."""
    from lenslab.errors import UsageError

    if value is None:
        return
    if fmt.kind != "image":
        raise UsageError(f"--pixel-type {value}: a clip's samples are its codec's (--codec) and its transfer's "
                         "(--transfer); --pixel-type applies to image outputs")
    held = fmt.pixel_types
    if value not in held:
        where = [f.title for f in _image_formats() if value in f.pixel_types]
        also = f"; {value} samples are written to {', '.join(where)}" if where else ""
        raise UsageError(f"--pixel-type {value}: {fmt.title} holds {' or '.join(held)} samples"
                         f"{'' if len(held) > 1 else ' only'}{also}")
    depth = integer_bits(value)
    if bits and depth and bits != depth:
        raise UsageError(f"--pixel-type {value} and --bits {bits} ask for two depths; give one of them")
    if bits and not depth:  # (--bits writes integers: a float type beside it is another sample type)
        raise UsageError(f"--pixel-type {value} asks for {value} samples and --bits {bits} for {bits}-bit integers; "
                         "give one of them")


def integer_bits(value: str | None) -> int | None:
    """8 of ``uint8``, 16 of ``uint16``; None for a float type or none."""
    return int(value[4:]) if value and value.startswith("uint") and value[4:].isdigit() else None


def pixel_type_options(value: str | None, default: str | None = None) -> dict:
    """The encode options (:func:`lenslab.jobs.stages.encode_options`) that write ``--pixel-type value`` (checked by
    :func:`check_pixel_type`): ``bits`` for integers, ``pixel_type`` (EXR) and ``sample_type`` (TIFF) for floats;
    ``default`` (the float type of an EXR when none is given) where ``value`` is None."""
    bits = integer_bits(value)
    if bits:
        return {"bits": bits}
    if value is None:
        return {"pixel_type": default}
    return {"pixel_type": value, "sample_type": value}


__all__ = ["pixel_type_choices", "check_pixel_type", "integer_bits", "pixel_type_options"]
