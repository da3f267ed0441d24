"""Real lenses from the lensfun database: the database look-up (:mod:`.database`), the profile as a lens
(:mod:`.profile`) and its compiled inverse (:mod:`.kernels`)."""
