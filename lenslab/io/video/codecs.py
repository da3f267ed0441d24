"""The video codecs lenslab writes and the containers it knows.

A table without heavy imports: the command line's ``--codec`` choices, format detection and the
encoder (:mod:`lenslab.io.video`) all read it.
"""

from __future__ import annotations

#: codec name -> (FFmpeg encoder, pixel format, bits)
CODECS = {"h264": ("libx264", "yuv420p", 8), "h265": ("libx265", "yuv420p10le", 10),
          "prores": ("prores_ks", "yuv422p10le", 10), "ffv1": ("ffv1", "yuv444p10le", 10)}
#: container extension -> default codec for SDR and for HDR (PQ/HLG) sources
DEFAULT_CODEC = {".mp4": ("h264", "h265"), ".m4v": ("h264", "h265"), ".mov": ("prores", "prores"),
                 ".mkv": ("ffv1", "ffv1")}
VIDEO_EXTENSIONS = tuple(DEFAULT_CODEC)
