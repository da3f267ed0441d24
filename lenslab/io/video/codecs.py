"""The video codecs lenslab writes and the containers it knows, and the opening of an encoder.

A table without heavy imports: the command line's ``--codec`` choices, format detection and the
encoder (:mod:`lenslab.io.video`) all read it (:func:`open_encoder` imports PyAV when called).
"""

from __future__ import annotations

#: codec name -> (FFmpeg encoder, pixel format, bits)
CODECS = {"h264": ("libx264", "yuv420p", 8), "h265": ("libx265", "yuv420p10le", 10),
          "prores": ("prores_ks", "yuv422p10le", 10), "ffv1": ("ffv1", "yuv444p10le", 10)}
#: container extension -> default codec for SDR and for HDR (PQ/HLG) sources
DEFAULT_CODEC = {".mp4": ("h264", "h265"), ".m4v": ("h264", "h265"), ".mov": ("prores", "prores"),
                 ".mkv": ("ffv1", "ffv1")}
VIDEO_EXTENSIONS = tuple(DEFAULT_CODEC)
#: encoders that refuse 4:2:0 frames of an odd width or height (as FFmpeg's libx264 and libx265 do)
ODD_4_2_0_REFUSED = ("libx264", "libx265")


def open_encoder(container, stream) -> None:
    """Open ``stream``'s encoder now instead of at its first frame (PyAV's default), with the options set so far:
    x264 allocates its lookahead and starts its threads here (about 5 ms at 1080p, 40 to 80 ms at 4K) while the
    caller makes its map and decodes its first frames, and a frame size or pixel format the encoder refuses is one
    error before any frame is made; ``container`` (an output PyAV container, nothing written yet) is closed then.
    A :class:`~lenslab.io.video.VideoWriter`'s encoder opened this way takes no further options."""
    import av

    from lenslab.errors import FormatError, cause

    cc = stream.codec_context
    need = {"yuv420": ("4:2:0", "an even width and height", cc.width % 2 or cc.height % 2),
            "yuv422": ("4:2:2", "an even width", cc.width % 2)}.get(cc.pix_fmt[:6])

    def refuse(why):
        container.close()
        raise FormatError(f"the {cc.name} encoder cannot encode {cc.width} x {cc.height} frames in {cc.pix_fmt}: "
                          f"{why}") from None

    if cc.name in ODD_4_2_0_REFUSED and need and need[0] == "4:2:0" and need[2]:
        # refused here, not by opening it: x265 would print its own lines on standard error first
        refuse(f"its {need[0]} chroma needs {need[1]}")
    try:
        cc.open(strict=False)  # what the first encode would do, with the same options
    except av.error.FFmpegError as exc:
        refuse(f"its {need[0]} chroma needs {need[1]}" if need and need[2] else cause(exc))
