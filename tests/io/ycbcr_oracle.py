"""An exact decoder for the video tests: each frame's Y'CbCr planes through colour-science's ``YCbCr_to_RGB`` (the
stream's BT.709 / BT.601 / BT.2020 matrix and H.273 range) in float64, chroma repeated over its block.

FFmpeg's swscale, the other decoder at hand, is not exact on its 16-bit RGB paths: it decodes a 10-bit white
(Y' = 940) to 65283/65535 (0.4 % low) and 8-bit codes at 8-bit precision (an 8-bit R' of 244.3 comes out as 242), so
it is an oracle with errors of its own."""

from __future__ import annotations

import colour
import numpy as np

#: H.273 matrix tags: 2 (unspecified) is BT.601, as FFmpeg codes and decodes an untagged clip (swscale's default;
#: tests/io/test_video_untagged_matrix.py holds lenslab to the ffmpeg command's own decode)
WEIGHTS = {1: "ITU-R BT.709", 2: "ITU-R BT.601", 5: "ITU-R BT.601", 6: "ITU-R BT.601", 9: "ITU-R BT.2020"}
LAYOUTS = {"yuv420p": (8, 1, 1), "yuv422p": (8, 1, 0), "yuv444p": (8, 0, 0), "yuv420p10le": (10, 1, 1),
           "yuv422p10le": (10, 1, 0), "yuv444p10le": (10, 0, 0)}


def exact_codes(frame, matrix: int, full: bool) -> np.ndarray:
    """A PyAV frame -> R'G'B' code values in [0, 1] (float64 H x W x 3), clipped as a decoder to RGB clips."""
    bits, hx, vy = LAYOUTS[frame.format.name]
    h, w = frame.height, frame.width
    dtype = np.uint8 if bits == 8 else np.uint16
    y, u, v = (np.frombuffer(p, dtype).reshape(p.height, p.line_size // dtype().itemsize) for p in frame.planes[:3])
    up = [np.repeat(np.repeat(c, 1 << vy, 0), 1 << hx, 1)[:h, :w] for c in (u, v)]
    return ycbcr_codes(np.stack([y[:h, :w], *up], -1), bits, matrix, full)


def ycbcr_codes(ycc: np.ndarray, bits: int, matrix: int, full: bool) -> np.ndarray:
    """Y'CbCr codes (..., 3, integers of ``bits`` bits) -> R'G'B' in [0, 1] (float64) by colour-science."""
    rgb = colour.YCbCr_to_RGB(np.asarray(ycc, np.float64), K=colour.WEIGHTS_YCBCR[WEIGHTS[matrix]], in_bits=bits,
                              in_legal=not full, in_int=True)
    return np.clip(rgb, 0.0, 1.0)


def decode_codes(path) -> list[np.ndarray]:
    """Every frame of the clip at ``path`` through :func:`exact_codes`, with its stream's matrix and range."""
    import av

    with av.open(str(path)) as c:
        s = c.streams.video[0]
        cc = s.codec_context
        return [exact_codes(f, int(cc.colorspace), int(cc.color_range) == 2) for f in c.decode(s)]


def write_ffv1(path, frames, pix_fmt: str = "yuv444p10le") -> None:
    """An FFV1 clip of ``frames`` (code values in [0, 1], H x W x 3 each) at 25 frames/s, BT.709 tags, converted
    to limited-range Y'CbCr by swscale (the clip's content only: tests decode it with :func:`decode_codes`)."""
    import av

    with av.open(str(path), "w") as c:
        s = c.add_stream("ffv1", rate=25)
        s.height, s.width = frames[0].shape[:2]
        s.pix_fmt = pix_fmt
        cc = s.codec_context
        cc.color_trc = cc.color_primaries = cc.colorspace = 1
        for i, v in enumerate(frames):
            f = av.VideoFrame.from_ndarray(np.round(v * 65535).astype(np.uint16), format="rgb48le")
            f = f.reformat(format=pix_fmt, dst_colorspace="itu709", src_color_range="JPEG", dst_color_range="MPEG")
            f.pts = i
            for p in s.encode(f):
                c.mux(p)
        for p in s.encode():
            c.mux(p)
