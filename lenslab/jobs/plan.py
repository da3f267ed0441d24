"""The one output planner of every batch command: which files the inputs name, where each one's output goes,
which are already done (``--skip-existing``), and the temporaries dead processes left there.

Everything here is checked before any file is read or folder made: a plan that cannot be carried out is an
error now, not one per file later.
"""

from __future__ import annotations

import glob
import os
from pathlib import Path
from typing import Callable


def _glob_root(pattern: str) -> str:
    """The folder a glob pattern starts from: its leading components without wildcards."""
    parts = Path(pattern).parts
    fixed = [p for p in parts[:next((i for i, p in enumerate(parts) if glob.has_magic(p)), len(parts))]]
    return str(Path(*fixed)) if fixed else "."


def expand_inputs(patterns: list[str], recursive: bool = False,
                  roots: dict[str, str] | None = None) -> tuple[list[str], list[tuple[str, str]]]:
    """Files to convert, and (input, reason) for inputs that match nothing.

    Directories give their image files (``recursive``: in every sub-folder too); ``**`` in a glob
    pattern matches any depth. ``roots`` (if given) receives, for every file found in a directory or
    by a pattern, the folder it was found under, so that outputs can mirror the tree.
    """
    from lenslab.io import split_selector
    from lenslab.io.registry import input_extensions

    files: list[str] = []
    missing: list[tuple[str, str]] = []
    roots = {} if roots is None else roots
    for pat in patterns:
        if os.path.isdir(pat):
            walk = Path(pat).rglob("*") if recursive else Path(pat).iterdir()
            found = sorted(str(p) for p in walk if p.is_file() and p.suffix.lower() in input_extensions())
            if not found:
                missing.append((pat, "the directory holds no image files"))
            files.extend(found)
            roots.update((f, pat) for f in found)
        elif glob.has_magic(pat) and not os.path.exists(pat):
            found = sorted(p for p in glob.glob(pat, recursive=True) if os.path.isfile(p))
            roots.update((f, _glob_root(pat)) for f in found)
            if not found:
                missing.append((pat, "the pattern matches no file"))
            files.extend(found)
        elif not split_selector(pat)[0].exists():  # (file.exr:part names a part of file.exr)
            missing.append((pat, "no such file or directory"))
        else:
            files.append(pat)
    seen: set[str] = set()
    unique = [f for f in files if not (f in seen or seen.add(f))]
    return unique, missing


def plan_outputs(files: list[str], output: str | None, extension: str | Callable[[Path], str],
                 roots: dict[str, str] | None = None, fmt: str | None = None,
                 verb: str = "convert") -> list[tuple[str, Path]]:
    """(input, output path) pairs for ``files``; raises before anything is made when ``-o`` cannot be used.

    ``output``: a file name (one input whose name has an extension), a folder (made later by the caller,
    once everything is checked), or None: next to each input. ``extension``: the outputs' extension with
    its dot, or a function of the input path giving it (a clip stays a clip). ``roots`` (from
    :func:`expand_inputs`): a file found under a folder goes to the same sub-folder of ``-o``, mirroring
    the input tree. ``fmt``: the format the command was told to write (``--to``, ``--format``); a file
    name ``-o`` of another format is a usage error, and so are an output that is one of the inputs and two
    inputs that would write one output (``verb`` words its message)."""
    from lenslab.errors import UsageError
    from lenslab.io import split_selector
    from lenslab.jobs.policy import check_output_dir, output_format, refuse_inputs

    ext_of = extension if callable(extension) else (lambda _src: extension)
    out = Path(output) if output is not None else None
    as_file = out is not None and len(files) == 1 and not out.is_dir() and out.suffix != ""
    if out is not None and not as_file:
        check_output_dir(out, len(files))
    if as_file and fmt is not None:
        named = output_format(out)  # an unknown extension: a usage error
        if named != fmt and not _same_kind(named, fmt):
            raise UsageError(f"-o {out}: the name says {named} but the output format asked is {fmt}; "
                             f"give -o NAME{ext_of(split_selector(files[0])[0])}, or the format the name says")
    pairs = []
    for f in files:
        src, selector = split_selector(f)
        stem = src.stem + (f"_{selector.replace(':', '_')}" if selector else "")
        if as_file:
            dst = out
        elif out is None:
            dst = src.with_name(stem + ext_of(src))
        else:
            sub = Path(os.path.relpath(src.parent, roots[f])) if roots and f in roots else Path(".")
            dst = out / sub / (stem + ext_of(src))
        pairs.append((f, dst))
    # usage errors, known from the names before any input is read: an output that is an input (also when
    # two inputs would write it), then two inputs that would write one output
    refuse_inputs(dict.fromkeys(dst for _, dst in pairs), (split_selector(f)[0] for f in files))
    targets: dict = {}
    for f, dst in pairs:
        if dst in targets:
            raise UsageError(f"{f} and {targets[dst]} would both be written to {dst}; {verb} them separately")
        targets[dst] = f
    return pairs


def _same_kind(a: str, b: str) -> bool:
    """Formats one file name may stand for (a .pnm name is written as PPM or PGM)."""
    return {a, b} <= {"ppm", "pgm"}


def skip_existing(pairs: list[tuple], skip: bool) -> tuple[list[tuple], int]:
    """With ``skip``, leave out the pairs whose output exists (a resumed batch); returns (pairs, skipped)."""
    if not skip:
        return pairs, 0
    left = [p for p in pairs if not Path(p[1]).exists()]
    return left, len(pairs) - len(left)


def sweep_outputs(pairs: list[tuple]) -> int:
    """Remove the temporaries that dead processes left in the output folders of ``pairs`` (a batch start
    and a ``--skip-existing`` resume); returns how many."""
    from lenslab.staging import sweep

    return len(sweep({Path(dst).parent for _, dst in pairs}))


__all__ = ["expand_inputs", "plan_outputs", "skip_existing", "sweep_outputs"]
