"""What every lens model builds on: the :class:`~lenslab.lenses.core.base.Lens` interface, the records
its hooks return (:mod:`~lenslab.lenses.core.protocol`), cameras and poses, camera files, and the
wrapper base for models that bend the image plane of another model. No models live here."""
