"""What a file says about its colour, and the way to Rec.709: the primaries conversion every reader and writer
shares (:mod:`~lenslab.io.colour.primaries`), PNG's cICP chunk (:mod:`~lenslab.io.colour.png_cicp`) and
embedded ICC profiles, read (:mod:`~lenslab.io.colour.icc`, :mod:`~lenslab.io.colour.icc_chunks`) and written
(:mod:`~lenslab.io.colour.icc_build`), and the colours of wider primaries that a display output clips
(:mod:`~lenslab.io.colour.gamut`)."""
