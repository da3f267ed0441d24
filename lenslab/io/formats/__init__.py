"""Format plugins: one module per format, each with a ``FORMATS`` tuple of
:class:`lenslab.io.plugin.Format` records (see :mod:`lenslab.io.registry`)."""
