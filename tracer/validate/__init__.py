"""Validation of lenslab warps against this tracer's direct renders.

- :mod:`tracer.validate.source`: a tracer scene as a validation source (:func:`~tracer.validate.source.make_source`);
- :mod:`tracer.validate.command`: the ``lenslab validate`` command (declared in the ``lenslab.commands``
  entry-point group, so it appears under ``lenslab`` while lenslab itself never imports the tracer).

The metrics, the run, the report, tuning and the amortised trade need no tracer and live in
:mod:`lenslab.validate`.
"""
