"""Projections: one image from one centre of projection, a formula from pixel to direction
(perspective, fisheyes, equirect, cylindrical, Pannini, world maps)."""
