"""Pure formulas on bare float64 arrays, shared by the lens models, each written once:

- :mod:`~lenslab.lenses.formulas.kinds`: the projection codes, enumerated once;
- :mod:`~lenslab.lenses.formulas.azimuthal`: the fisheye mappings (equidistant, equisolid,
  stereographic, orthographic, Thoby);
- :mod:`~lenslab.lenses.formulas.lonlat`: longitude and latitude, the equirectangular and cylindrical
  spacings (central, Lambert equal-area, Mercator);
- :mod:`~lenslab.lenses.formulas.calibrated`: the calibrated models' projections (pinhole, FOV,
  equidistant, Mei's unified, double sphere, EUCM);
- :mod:`~lenslab.lenses.formulas.radial`: radial polynomials ``r_d = r_u P(r_u)`` and their inverse;
- :mod:`~lenslab.lenses.formulas.solve`: the one safeguarded Newton that inverts the maps with no
  closed-form inverse.

Each NumPy function has its compiled C++ twin in ``src/native/lens_formulas.h`` (the extension
``lenslab.cxx_kernels``), fused there into the models' kernels; :mod:`~lenslab.lenses.formulas.reference`
composes the NumPy functions into each kernel's reference, and the tests hold each pair to each other and
to published values. No models live here.
"""
