"""Benchmarks behind ``lenslab bench``: each module has ``add_arguments(parser)`` and ``run(args)``."""
