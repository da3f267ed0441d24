"""Batch work on a Dask cluster: one task per file, the scheduler of the scientific Python world.

``lenslab warp``, ``convert``, ``tonemap`` and ``validate`` take ``--scheduler tcp://host:8786`` or
``--scheduler-file FILE`` (or ``DASK_SCHEDULER_ADDRESS`` in the environment) and then send each file
to the workers of that cluster (``dask scheduler`` and ``dask worker`` on any machines sharing the file
system, or SLURM through dask-jobqueue). Without them, the batch runs on this machine as before.

- :mod:`lenslab.cluster.connect`: where the scheduler is, and the client to it;
- :mod:`lenslab.cluster.run`: submit, follow with a progress bar, cancel on Ctrl-C, a lost scheduler;
- :mod:`lenslab.cluster.tasks`: a worker's share of the machine's threads;
- :mod:`lenslab.cluster.threads`: the same batch on threads of this process.

What a task does is a job (:mod:`lenslab.jobs`): the workers write each output to a temporary and the
command renames it (:mod:`lenslab.jobs.runner`), so an output is complete or absent, and none appears
once the command has ended; a worker killed mid-task has its files done again by another worker.
"""

from __future__ import annotations

from lenslab.cluster.connect import scheduler_address

__all__ = ["scheduler_address"]
