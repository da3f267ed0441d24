"""tracer: a compact reference ray tracer for lenslab cameras (pyvista scenes, embree ray casts)."""
