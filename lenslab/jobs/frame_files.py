"""A clip written as image files, one per frame (``lenslab convert`` and ``lenslab warp``): the frames' names
(``NAME.000042.exr``, or the frame number where the name has ``%04d``), their all-or-none writing, and the
folder a sequence's name asks for."""

from __future__ import annotations

import re
from pathlib import Path

#: a printf-style frame number in an output name (``%d``, ``%04d``), as FFmpeg's image sequences take it
FRAME_NUMBER = re.compile(r"%(0?\d*)d")


def frame_path(dst, index: int) -> Path:
    """``out/clip.exr`` -> ``out/clip.000042.exr``, and ``out/%04d.exr`` -> ``out/0042.exr`` (the first
    ``%d`` or ``%0Nd`` of the file name): frame numbers as in the clip, from 0.

    >>> frame_path("out/clip.exr", 42).as_posix(), frame_path("out/f_%04d.png", 7).as_posix()
    ('out/clip.000042.exr', 'out/f_0007.png')
    """
    d = Path(dst)
    if FRAME_NUMBER.search(d.name):
        return d.with_name(FRAME_NUMBER.sub(lambda m: f"{index:{m.group(1)}d}", d.name, count=1))
    return d.with_name(f"{d.stem}.{index:06d}{d.suffix}")


def frame_output(dst, index: int, src, overwrite: bool) -> Path:
    """:func:`frame_path`, checked as every output is (:func:`lenslab.jobs.policy.check_output`): an existing
    frame file is replaced only with ``overwrite``, and the error names that file alone."""
    from lenslab.jobs.policy import check_output

    path = frame_path(dst, index)
    if not FRAME_NUMBER.search(Path(dst).name):  # a name made of the clip's or -o's, longer by the frame number
        from lenslab.atomic import name_too_long

        why = name_too_long(path)
        if why:
            from lenslab.errors import OutputError

            numbered = Path(dst).parent / f"%06d{Path(dst).suffix}"
            exc = OutputError(f"{why.rsplit('; ', 1)[0]} (a frame is named NAME.NUMBER{Path(dst).suffix}); name the "
                              f"frames by their number alone: -o '{numbered}'")
            exc.lenslab_file = why.partition(": ")[0]
            raise exc
    return check_output(path, [src], overwrite)


def names_output(line: str, dst) -> bool:
    """Whether an error ``line`` is about the output ``dst`` itself, or one of the frame files a clip written
    to ``dst`` takes (:func:`frame_path`): it starts with that file's name. Such a line names the output alone.

    >>> names_output("out/clip.000042.exr: already exists", "out/clip.exr"), names_output("a.exr: bad", "a.png")
    (True, False)
    """
    first, sep, _ = str(line).partition(": ")
    d, named = Path(dst), Path(first)
    if not sep or named.parent != d.parent:
        return False
    if first == str(dst):
        return True
    found = FRAME_NUMBER.search(d.name)
    pattern = (re.escape(d.name[:found.start()]) + r"\d+" + re.escape(d.name[found.end():]) if found
               else re.escape(d.stem) + r"\.\d{6,}" + re.escape(d.suffix))
    return re.fullmatch(pattern, named.name) is not None


def all_or_none(write_frames):
    """Call ``write_frames()`` (which writes each frame with :func:`lenslab.io.write`) so that its files are
    temporaries until the last is written, then renamed (:func:`lenslab.staging.staged`); a failure (a damaged
    frame, a frame of another size, Ctrl-C) removes them and leaves the folder as it was. A cluster task's
    writes are already staged: the command renames them, or removes them when the task failed. Returns what
    ``write_frames`` returns."""
    from lenslab.atomic import STAGING, owner
    from lenslab.staging import commit, staged

    if getattr(STAGING, "owner", None) is not None:
        return write_frames()
    with staged(owner()) as written:
        result = write_frames()
        commit(written)
    return result


def sequence_folder(pairs, is_clip) -> Path | None:
    """The folder to make for a single clip written as image files (``-o 'frames/%04d.png'`` or
    ``-o frames/shot.png``) when it does not exist yet, as ``-o DIR`` is made; else None. ``is_clip(src)``
    says whether an input is a clip."""
    from lenslab.io.video.codecs import VIDEO_EXTENSIONS

    if len(pairs) != 1:
        return None
    src, dst = pairs[0]
    folder = Path(dst).parent
    if Path(dst).suffix.lower() in VIDEO_EXTENSIONS or folder.is_dir() or not is_clip(src):
        return None  # a clip to a clip, a folder already there, a still image (written to a name as it is)
    return folder


def note_frames(written: int, first, last) -> None:
    """The note of a clip written as images (``-o f.exr``: f.000000.exr ...): how many, the first and the last,
    which are not the one file the output's name says."""
    if written > 1:
        import warnings

        warnings.warn(f"{written} frames written: {first} to {last}", UserWarning, stacklevel=3)


def in_sequence_folder(pairs, is_clip, run) -> int:
    """``run()`` (a batch: its exit status) with the :func:`sequence_folder` of ``pairs`` made first, as
    ``-o DIR`` is made (every check of the command has passed), and removed again, with the parents it
    needed, when the batch failed having written nothing there."""
    from lenslab.jobs.policy import make_output_dir, remove_made_dirs

    folder, made = sequence_folder(pairs, is_clip), []
    if folder is not None:
        make_output_dir(folder, made)
    try:
        status = run()
    except BaseException:
        remove_made_dirs(made)
        raise
    if status:
        remove_made_dirs(made)
    return status


__all__ = ["FRAME_NUMBER", "frame_path", "frame_output", "names_output", "all_or_none", "sequence_folder",
           "note_frames", "in_sequence_folder"]
