"""Validation of warps against direct renders, and the speed/accuracy trade.

- :mod:`~lenslab.validate.sources`: what a render is, and the noise-free analytic environment (the
  ray tracer's scenes are sources of :mod:`tracer.validate.source`);
- :mod:`~lenslab.validate.run`: reference, panoramas, warps, timings and metrics (:func:`validate`);
- :mod:`~lenslab.validate.report`: ``results.json``, ``report.md`` and the plots;
- :mod:`~lenslab.validate.tune`: the cheapest setting for a target error;
- :mod:`~lenslab.validate.amortised`: K views from one panorama against K direct renders.

Nothing here imports the tracer: any object with ``render(camera, spp, seed)`` is a source. The
``lenslab validate`` command lives with the tracer (:mod:`tracer.validate.command`).
"""
