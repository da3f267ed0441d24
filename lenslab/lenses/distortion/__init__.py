"""Distortions applied in front of a base model: the division model (pincushion, barrel), the Brown
polynomial, the swirl, and chromatic aberration with vignetting. The division model itself is
:mod:`lenslab.lenses.distortion.division`."""
