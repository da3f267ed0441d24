"""Batch work on a Dask cluster: one task per file, the scheduler of the scientific Python world.

``lenslab warp``, ``convert``, ``tonemap`` and ``validate`` take ``--scheduler tcp://host:8786`` or
``--scheduler-file FILE`` (or ``DASK_SCHEDULER_ADDRESS`` in the environment) and then send each file
to the workers of that cluster (``dask scheduler`` and ``dask worker`` on any machines sharing the file
system, or SLURM through dask-jobqueue). Without them, the batch runs on this machine as before.

- :mod:`lenslab.cluster.connect`: where the scheduler is, and the client to it;
- :mod:`lenslab.cluster.run`: submit, follow with a progress bar, cancel on Ctrl-C, sweep temporaries;
- :mod:`lenslab.cluster.tasks`: what runs on a worker (a warp's map made once per worker and reused).

Outputs are written by the workers to a temporary name and renamed (:mod:`lenslab.io.atomic`), so an
output is complete or absent; a worker killed mid-task has its files done again by another worker.
"""

from __future__ import annotations

from lenslab.cluster.connect import scheduler_address

__all__ = ["scheduler_address"]
