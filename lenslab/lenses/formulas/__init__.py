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

Each NumPy function has its compiled (numba) twin in the ``*_kernels`` module beside it, imported on
first use; the tests hold each pair to each other and to published values. No models live here.
"""
