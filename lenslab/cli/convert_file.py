"""One file of ``lenslab convert``: read it, render it for the target format, write it.

Kept apart from :mod:`lenslab.cli.convert` (argument parsing and batch planning) so the task runners of
:mod:`lenslab.cluster` can call it without importing the command.
"""

from __future__ import annotations


def convert_one(src: str, dst: str, options: dict) -> str:
    """Read, tone-map if needed, write. Returns the output path; raises on failure."""
    from lenslab.cli.policy import check_output
    from lenslab.io import read, split_selector, write

    src_file, _ = split_selector(src)
    check_output(dst, [src_file], options["overwrite"])
    from lenslab.cli.warp_video import is_video

    if is_video(src_file):  # a clip: one file per frame
        from lenslab.cli.convert_video import frames_to_files

        return frames_to_files(str(src_file), dst, options)
    image, meta = read(src, data_window=options["data_window"])
    from lenslab.cli.render import render

    image, write_opts = render(image, meta, options)
    write(dst, image, format=options["to"], overwrite=options["overwrite"], **write_opts)
    return dst
