"""Pure formulas on bare float64 arrays, shared by the lens models: the projections of a direction to
an image-plane radius and back (:mod:`~lenslab.lenses.formulas.azimuthal`), radial polynomials
(:mod:`~lenslab.lenses.formulas.radial`) and the one safeguarded Newton that inverts the maps with no
closed-form inverse (:mod:`~lenslab.lenses.formulas.solve`). Each NumPy function has a compiled (numba)
twin in the ``*_kernels`` module beside it, imported on first use. No models live here."""
