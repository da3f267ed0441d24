"""Validation of warps against direct renders, and the speed/accuracy trade.

- :mod:`~lenslab.validate.sources`: what is rendered (a tracer scene, or a noise-free analytic
  environment);
- :mod:`~lenslab.validate.run`: reference, panoramas, warps, timings and metrics (:func:`validate`);
- :mod:`~lenslab.validate.report`: ``results.json``, ``report.md`` and the plots;
- :mod:`~lenslab.validate.tune`: the cheapest setting for a target error;
- :mod:`~lenslab.validate.amortised`: K views from one panorama against K direct renders.

Nothing here imports the tracer at module level: :class:`~lenslab.validate.sources.TracerSource`
imports it when a tracer scene is asked for.
"""
