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
#: the smallest side x265 encodes, across and down (it refuses 14 and less either way; 16 x 16 encodes: tried
#: through PyAV in tests/io/test_video_x265_min_size.py)
X265_MIN_SIDE = 16
#: frames with a side below this are encoded by x265 without its CU-tree (see :func:`x265_params`)
X265_CUTREE_SIDE = 64


def check_clip_size(size: tuple[int, int], path, codec: str | None) -> None:
    """A :class:`~lenslab.errors.UsageError` for an output size given on the command line that the clip's encoder
    refuses (an odd side in 4:2:0, which x264 and x265 cannot encode; a side under :data:`X265_MIN_SIDE` with
    ``--codec h265``), before any frame is decoded; ``codec``:
    ``--codec``, None for the default of ``path``'s extension (H.264 or H.265 in .mp4, both 4:2:0)."""
    from pathlib import Path

    from lenslab.errors import UsageError

    w, h = size
    if codec and CODECS[codec][0] == "libx265" and min(w, h) < X265_MIN_SIDE:  # (the default H.265 of an HDR
        # clip in .mp4 is known only once the clip is probed: check_encodes then, exit 1)
        raise UsageError(f"--size {w}x{h}: the libx265 encoder (--codec h265) encodes frames of at least "
                         f"{X265_MIN_SIDE} x {X265_MIN_SIDE}; give --size {max(w + w % 2, X265_MIN_SIDE)}x"
                         f"{max(h + h % 2, X265_MIN_SIDE)} or larger, or --codec h264 for an SDR clip")  # (before the probe:
        # whether the clip is PQ/HLG, which H.264 in .mp4 would not keep as HDR, is not known yet)
    for name in [codec] if codec else DEFAULT_CODEC.get(Path(path).suffix.lower(), ()):
        encoder, pix_fmt, _ = CODECS[name]
        if encoder in ODD_4_2_0_REFUSED and pix_fmt.startswith("yuv420") and (w % 2 or h % 2):
            raise UsageError(f"--size {w}x{h}: the {encoder} encoder of this clip writes 4:2:0 ({pix_fmt}), whose "
                             f"chroma needs an even width and height; give --size {w + w % 2}x{h + h % 2}, or "
                             "--codec ffv1 (4:4:4)")


def chosen_codec(path, codec: str | None, curve: str | None) -> str:
    """The codec a clip written to ``path`` is encoded with: ``codec`` (--codec), else its extension's default
    (:data:`DEFAULT_CODEC`) for SDR frames, or for HDR ones where ``curve`` is ``"pq"`` or ``"hlg"``."""
    from pathlib import Path

    if codec:
        return codec
    sdr, hdr = DEFAULT_CODEC.get(Path(path).suffix.lower(), ("h264", "h265"))
    return hdr if curve in ("pq", "hlg") else sdr


def check_encodes(size: tuple[int, int], path, codec: str | None, curve: str | None, larger: str = "frames of") -> None:
    """A :class:`~lenslab.errors.FormatError` in one line where the encoder :func:`chosen_codec` picks refuses frames
    of ``size`` (W, H): H.265 under :data:`X265_MIN_SIDE` a side, whether ``--codec h265`` asked for it or the
    extension picked it for a PQ/HLG clip (``curve``), known once the clip is probed. Called before the output (or its
    temporary) is made and before any frame is decoded; ``larger`` leads the size to give (``--size``); ``"clip"``:
    the frames are a clip's, whose size convert keeps (``lenslab warp --size`` enlarges it)."""
    from pathlib import Path

    from lenslab.errors import FormatError

    w, h = (int(v) for v in size)
    if CODECS.get(chosen_codec(path, codec, curve), ("",))[0] != "libx265" or min(w, h) >= X265_MIN_SIDE:
        return
    hdr = curve in ("pq", "hlg")
    chosen = "--codec h265" if codec else (f"H.265, {Path(path).suffix.lower()}'s codec for "
                                                 f"{'an' if curve == 'hlg' else 'a'} {str(curve).upper()} clip")
    other = ("-o NAME.mov (ProRes) or NAME.mkv (FFV1), which keep its 10 bits" if hdr else "--codec h264")
    wanted = (" x " if larger == "frames of" else "x").join(str(max(v + v % 2, X265_MIN_SIDE)) for v in (w, h))
    way = (f"convert keeps a clip's size: give {other}, or enlarge it with lenslab warp --to SPEC --size {wanted}"
           if larger == "clip" else f"give {larger} {wanted} or larger, or {other}")
    raise FormatError(f"the libx265 encoder ({chosen}) encodes frames of at least {X265_MIN_SIDE} x {X265_MIN_SIDE}, "
                      f"not {w} x {h}: {way}")


def x265_params(width: int, height: int) -> str:
    """The ``x265-params`` lenslab gives libx265 for ``width`` x ``height`` frames.

    x265's CU-tree (the lookahead's propagation of each block's cost to the frames that reference it) corrupts the
    heap or segfaults on some small frames. Measured on x265 4.2 (in PyAV's wheels), several frames of noise each:
    every even width from 34 to 48 crashed at each height tried (32, 34, 64, 66); widths 16 to 32 and 50 to 58 at
    those heights, 60 to 300 at 64 high, and 64 wide at 16 to 60 high encoded; with 16-pixel CTUs 34 to 48 x 34 to
    48 crashed too. Without CU-tree nothing crashed in a grid of every even width from 16 to 66 (and 96, 128) by 13
    heights from 16 to 96. So frames with a side under one 64-pixel CTU (where x265 picks a smaller CTU itself) are
    encoded without CU-tree; larger frames get x265's defaults unchanged, byte for byte."""
    small = min(width, height) < X265_CUTREE_SIDE
    return "log-level=error" + (":cutree=0" if small else "")


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

    way_out = "; --codec ffv1 (4:4:4) encodes them"  # (frames that bring their own size: no --size changes it)
    if cc.name in ODD_4_2_0_REFUSED and need and need[0] == "4:2:0" and need[2]:
        # refused here, not by opening it: x265 would print its own lines on standard error first
        refuse(f"its {need[0]} chroma needs {need[1]}{way_out}")
    try:
        cc.open(strict=False)  # what the first encode would do, with the same options
    except av.error.FFmpegError as exc:
        refuse(f"its {need[0]} chroma needs {need[1]}{way_out}" if need and need[2] else cause(exc))


#: the widest a dts may trail its pts, in frames (x265 reorders at most 16 B-frames, in a pyramid): a dts further back
#: is no encoder's reordering but a value it left undefined
DTS_REORDER_SPAN = 64


def mux_video(container, packets, last: list) -> None:
    """Mux ``packets`` of a video encoder into ``container``, each decoding time (dts) that is undefined (None, after
    its pts, further back than :data:`DTS_REORDER_SPAN` frames, or not after the previous one) set to the packet's pts
    (kept after the previous dts): libx265 flushing one or two frames hands its first packet back with an uninitialised
    dts, which the MP4 muxer refuses ("pts/dts pair unsupported"). ``last``: a one-item list, the last dts muxed (None
    before the first packet), carried from one call to the next."""
    for packet in packets:
        pts, dts = packet.pts, packet.dts
        if pts is not None and (dts is None or dts > pts or dts < pts - DTS_REORDER_SPAN
                                or (last[0] is not None and dts <= last[0])):
            repaired = pts if last[0] is None else min(pts, last[0] + 1)
            if last[0] is None or repaired > last[0]:
                packet.dts = repaired
        if packet.dts is not None:
            last[0] = packet.dts
        container.mux(packet)

