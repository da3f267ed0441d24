"""360 formats: whole-sphere layouts of video and VR (cube maps, EAC, dual fisheye, octahedron) and the
named presets of other models (half-equirect, little planet)."""
