"""Several cameras in one image: tiled multi-view grids (each tile its own lens, pose and eye)."""
