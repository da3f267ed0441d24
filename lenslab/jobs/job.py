"""What every job is: the options of one batch command, frozen, with ``run(input, output)`` for one file.

A job is plain data: the runner (:mod:`lenslab.jobs.runner`) hands the same object to threads of this
process or pickles it to the workers of a Dask cluster. A new batch command is one job class (its fields
are its options) and one parser in :mod:`lenslab.cli` that fills them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, fields, replace
from typing import ClassVar


@dataclass(frozen=True)
class Job:
    """Base of the typed jobs: ``overwrite`` is every job's; subclasses add their options as fields."""

    #: the command's name (``lenslab warp``) and its past tense for the summary line
    command: ClassVar[str] = "run"
    verb: ClassVar[str] = "processed"
    #: the fields that may name files: made absolute before the job goes to workers (their own folder)
    paths: ClassVar[tuple[str, ...]] = ()

    overwrite: bool = False

    def run(self, src: str, dst: str, progress=None) -> None:
        """Do the work of one file: read ``src``, write ``dst`` (through a temporary). Raises on failure;
        repairs are warnings (the file's notes)."""
        raise NotImplementedError

    @classmethod
    def from_options(cls, options, **values):
        """The job whose fields take their values from ``options`` (an argparse namespace or a dict, extra
        keys ignored), then from ``values``."""
        get = options.get if isinstance(options, dict) else (lambda k, d=None: getattr(options, k, d))
        given = {f.name: get(f.name) for f in fields(cls) if get(f.name, _MISSING) is not _MISSING}
        return cls(**{**given, **values})

    def for_workers(self):
        """This job with the files its options name made absolute (workers have their own folder)."""
        changes = {k: os.path.abspath(v) for k in self.paths
                   if isinstance(v := getattr(self, k, None), str) and os.path.exists(v)}
        return replace(self, **changes) if changes else self


_MISSING = object()

__all__ = ["Job"]
