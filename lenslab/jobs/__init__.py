"""Batch work, once for every command: typed jobs (:mod:`~lenslab.jobs.warp`, :mod:`~lenslab.jobs.convert`,
:mod:`~lenslab.jobs.tonemap`), the output planner (:mod:`~lenslab.jobs.plan`), the output policy
(:mod:`~lenslab.jobs.policy`), the look and encode stages (:mod:`~lenslab.jobs.stages`), the runner on
threads or Dask (:mod:`~lenslab.jobs.runner`), the error funnel and stop signals
(:mod:`~lenslab.jobs.funnel`) and the argument types every command shares (:mod:`~lenslab.jobs.arguments`).

The command line (:mod:`lenslab.cli`) turns arguments into jobs and prints; the cluster's workers, the
benchmarks, the tracer and the gallery use this package, never the command line. Submodules are imported
where they are used (``--help`` stays instant).
"""
