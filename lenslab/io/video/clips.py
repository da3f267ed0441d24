"""Video through PyAV: frames decoded to linear light, and linear frames encoded back, colour tags kept.

Decoding: each frame's Y'CbCr planes go to linear light in one compiled pass, exact to the stream's matrix
(BT.709, BT.601 or BT.2020) and range, through a table of colour-science's transfer function chosen by the
stream's transfer tag (:mod:`lenslab.io.video.ycbcr`; encoding is the same pass backwards). HLG, RGB-coded
streams and other pixel formats go through FFmpeg's swscale to 16-bit RGB first (:mod:`lenslab.io.video.colour`).
Decoding runs on a thread ahead of the caller:

- BT.709 / BT.601 / BT.2020 SDR / unspecified: the BT.1886 display EOTF (gamma 2.4, black 0, white 1)
- sRGB (IEC 61966-2-1): the sRGB EOTF; also an RGB-coded stream (FFV1 or x264rgb: matrix ``gbr`` or an RGB
  pixel format) with no transfer tag, which holds what its image frames held. Such a stream is read at its
  own depth without swscale's matrix and written back as RGB (FFV1 planar RGB, 10-bit), so a clip and its
  PNG frames warp alike
- PQ (SMPTE ST 2084): absolute luminance in cd/m^2 divided by 203 (BT.2408 HDR reference white = 1.0)
- HLG (ARIB STD-B67): BT.2100's HLG EOTF for a 1000 cd/m^2 display, divided by 203 likewise

BT.2020 primaries are converted to linear Rec.709 (lenslab's working space; wide-gamut colours give
negative components, kept) and back on encoding. Encoding applies the inverse of the same functions
and writes the input's tags (primaries, transfer, matrix, range) unless told otherwise.

Codecs (``CODECS``): ``h264`` (libx264, 8-bit 4:2:0), ``h265`` (libx265, 10-bit 4:2:0), ``prores``
(prores_ks 4:2:2 10-bit) and ``ffv1`` (lossless, 10-bit 4:4:4). Audio streams are copied packet for
packet when the whole clip is written.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError, cause
from lenslab.io.video.codecs import CODECS, DEFAULT_CODEC, VIDEO_EXTENSIONS, mux_video, x265_params  # noqa: F401
from lenslab.io.video.colour import DISPLAY_TAGS, display_tags  # noqa: F401  (re-exported)
from lenslab.io.video.opened import identity, probing, take
from lenslab.io.video.ycbcr import RowsToYCbCr, exact, ycbcr_frame, ycbcr_to_linear
from lenslab.io.video.colour import (REFERENCE_WHITE, BT2020, decode_table, is_wide,  # noqa: F401  (re-exported)
                                     codes16_to_linear, codes16_to_linear_compiled, from_linear,
                                     linear_to_codes16, to_linear)

# FFmpeg's enum values (libavutil/pixfmt.h)
_TRC = {1: "bt1886", 6: "bt1886", 14: "bt1886", 15: "bt1886", 2: "bt1886", 13: "srgb", 16: "pq", 18: "hlg"}
_SWS = {1: "itu709", 2: "itu601", 5: "itu601", 6: "smpte170m", 9: "bt2020", 10: "bt2020"}  # 2: as FFmpeg (H273_YCBCR)
_RGB_MATRIX = 0  # AVCOL_SPC_RGB: the planes are G, B, R
_RGB_PIXELS = ("gbr", "bgr", "rgb", "argb", "abgr", "0rgb", "0bgr")  # FFmpeg's RGB pixel formats
_THREADS = 2  # swscale's threads for a frame's matrix and range (the decoder and encoder have their own)
_UNSPECIFIED = (0, 2)  # AVCOL_TRC_RESERVED0, AVCOL_TRC_UNSPECIFIED
#: the planar RGB pixel format of each codec's YUV format, for RGB-coded streams (same bits)
_RGB_FORMATS = {"yuv444p10le": "gbrp10le", "yuv444p": "gbrp"}


@dataclass
class VideoInfo:
    """What a video stream holds, and the tags written back."""

    width: int
    height: int
    rate: Fraction
    frames: int
    codec: str
    pixel_format: str
    primaries: int = 1
    transfer: int = 1
    matrix: int = 1
    range: int = 1
    audio: bool = False
    extra: dict = field(default_factory=dict)

    @property
    def rgb(self) -> bool:
        """Whether the stream codes R, G, B themselves (matrix tag 0, FFV1 or x264rgb ``gbr``), not Y'CbCr."""
        return self.matrix == _RGB_MATRIX or self.pixel_format.startswith(_RGB_PIXELS)

    @property
    def curve(self) -> str:
        # an RGB-coded stream without a transfer tag holds what image files hold, sRGB-encoded colour
        # (ffmpeg -i frame%d.png -c:v ffv1 leaves the tag unspecified): decoded as its PNG frames are
        if self.rgb and self.transfer in _UNSPECIFIED:
            return "srgb"
        return _TRC.get(self.transfer, "bt1886")

    @property
    def hdr(self) -> bool:
        return self.curve in ("pq", "hlg")


def _av():
    try:
        import av
    except ImportError:
        raise FormatError("video needs PyAV: pip install 'lenslab[video]'") from None
    return av


def _open(path):
    av = _av()
    try:
        return av.open(str(path))
    except av.error.FFmpegError as exc:
        raise FormatError(f"{path}: FFmpeg cannot open it as a video ({cause(exc)})") from None


#: the streams of the last few files probed, by path, size, modification and status-change times and inode: a command
#: probes its input for the budget, for the warp and for decoding, and FFmpeg's probe decodes frames (50 ms for a 4K
#: H.264 clip)
_PROBED: dict = {}


def probe_video(path) -> VideoInfo:
    """What the video stream of ``path`` holds (a new :class:`VideoInfo` each call)."""
    from dataclasses import replace

    key = identity(path)
    if key is None or key not in _PROBED:
        info = _probe(path, key)
        if key is None:
            return info
        if len(_PROBED) >= 8:
            _PROBED.clear()
        _PROBED[key] = info
    info = _PROBED[key]
    return replace(info, extra=dict(info.extra))


def _probe(path, key=None) -> VideoInfo:
    with probing(_open(path), key) as c:  # the open clip is then held for its decoder
        if not c.streams.video:
            raise FormatError(f"{path}: the file holds no video stream")
        s = c.streams.video[0]
        cc = s.codec_context
        if cc is None or not cc.width or not cc.height:
            raise FormatError(f"{path}: the video stream has no decoder or no frame size; the file is damaged")
        rate = s.average_rate or s.guessed_rate
        if not rate or not s.time_base:
            raise FormatError(f"{path}: the video stream declares no frame rate; the file is damaged")
        frames = int(s.frames) or (int(round(float(s.duration * s.time_base * rate))) if s.duration else 0)
        return VideoInfo(cc.width, cc.height, Fraction(rate), frames, cc.name,
                         cc.pix_fmt or "", int(cc.color_primaries), int(cc.color_trc), int(cc.colorspace),
                         int(cc.color_range), bool(c.streams.audio))


def _range(info: VideoInfo) -> str:
    return "JPEG" if info.range == 2 else "MPEG"


def frame_codes16(frame, info: VideoInfo) -> np.ndarray:
    """A decoded PyAV frame -> 16-bit code values (uint16 H x W x 3), converted with the stream's matrix."""
    rgb = frame.reformat(format="rgb48le", src_colorspace=_SWS.get(info.matrix, "itu709"),
                         src_color_range=_range(info), dst_color_range="JPEG", threads=_THREADS)
    return rgb.to_ndarray()


def frame_codes(frame, info: VideoInfo) -> np.ndarray:
    """A decoded PyAV frame -> float64 code values in [0, 1], H x W x 3, converted with the stream's matrix."""
    if info.rgb:  # RGB-coded: no matrix; the codes exactly, at the stream's own depth (swscale's
        # conversions of 8-bit bgr0 to 16-bit RGB are off by up to 0.7 % of the code)
        bits = max(c.bits for c in frame.format.components)
        if frame.format.name.startswith("gbrp") and bits > 8:
            return frame.to_ndarray().astype(np.float64) / float((1 << bits) - 1)
        if bits <= 8:
            return frame.to_ndarray(format="rgb24").astype(np.float64) / 255.0
        return frame.to_ndarray(format="rgb48le").astype(np.float64) / 65535.0
    return frame_codes16(frame, info).astype(np.float64) / 65535.0


def read_frames(path, start: int = 0, stop: int | None = None, prefetch: int = 3, window=None):
    """Yield (index, linear float32 H x W x 3) for frames ``start <= index < stop``.

    Decoding runs on a thread of its own, ``prefetch`` frames ahead of the caller (PyAV and the compiled passes
    release the GIL), so a warp of each frame overlaps the next decode; so does the conversion to linear light,
    except with ``window``.

    ``window``: a function called for each frame, giving None (the whole frame), ``(row0, row1, col0, col1)`` or each
    row's spans of columns (``H x 4``, :func:`lenslab.warp.taps.source_spans`): the pixels a warp reads, the only ones
    converted to linear light. Y'CbCr frames are then converted in the caller's thread as it takes them, into one
    buffer reused frame to frame (a 4K frame is 88 MB of fresh pages otherwise): each frame is valid until the
    caller takes the next, and outside the window it holds 0 or an earlier frame's values."""
    info = probe_video(path)
    if info.curve != "hlg":  # the table is built here, so that an error in it surfaces in this thread
        decode_table(info.curve, is_wide(info.primaries))

    held = take(identity(path))  # the probe's open clip, decoded from its first packet

    def frames():  # on the decoding thread
        with held or _open(path) as c:
            stream = c.streams.video[0]
            stream.thread_type = "AUTO"
            frames = c.decode(stream)
            i = -1
            while True:
                try:
                    frame = next(frames)
                except StopIteration:
                    return
                except _av().error.FFmpegError as exc:  # damaged frame data
                    raise FormatError(f"{path}: FFmpeg cannot decode frame {i + 2} ({str(exc)[:80]}); the file "
                                      "is damaged") from None
                i += 1
                if stop is not None and i >= stop:
                    break
                if i >= start and (frame.width, frame.height) != (info.width, info.height):
                    raise FormatError(f"{path}: frame {i} (counting from 0) is {frame.width} x {frame.height}, not "
                                      f"{info.width} x {info.height} as the clip declares: the frame size changes "
                                      "mid-stream; re-encode the clip at one size (e.g. ffmpeg -i CLIP -vf "
                                      f"scale={info.width}:{info.height} OUT)")
                if i >= start and info.rgb:  # RGB-coded: its codes exactly, at its own depth
                    yield i, to_linear(frame_codes(frame, info), info)
                elif i >= start:
                    if not exact(info, frame.format.name):  # swscale's path (HLG, other formats and matrices)
                        yield i, codes16_to_linear_compiled(frame_codes16(frame, info), info)
                    elif window is None:
                        yield i, ycbcr_to_linear(frame, info)
                    else:  # converted by the caller, where it reads
                        yield i, frame

    from lenslab.io.video.prefetch import ahead

    buffer: list = []
    for i, item in ahead(frames(), prefetch):
        if isinstance(item, np.ndarray):
            yield i, item
            continue
        box = window()
        if box is not None and (len(box) != item.height if isinstance(box, np.ndarray) else box[1] > item.height
                                or box[3] > item.width):
            yield i, ycbcr_to_linear(item, info)  # a frame of another size than the stream declared: the warp says so
            continue
        if not buffer or buffer[0].shape != (item.height, item.width, 3):
            buffer[:] = [np.zeros((item.height, item.width, 3), np.float32)]
        yield i, ycbcr_to_linear(item, info, (0, item.height, 0, item.width) if box is None else box, buffer[0])


class VideoWriter:
    """Encode linear frames to ``path`` with ``codec`` and ``info``'s rate and colour tags.

    ``audio_from``: a video whose audio streams are copied into the output when it closes.
    """

    def __init__(self, path, info: VideoInfo, codec: str | None = None, size: tuple[int, int] | None = None,
                 audio_from=None):
        av = _av()
        from lenslab.io.video.codecs import check_encodes, chosen_codec

        check_encodes(size or (info.width, info.height), path, codec, info.curve)  # before the file is made
        codec = chosen_codec(path, codec, info.curve)
        if codec not in CODECS:
            raise FormatError(f"unknown video codec {codec!r}; choose one of {', '.join(CODECS)}")
        encoder, pix_fmt, bits = CODECS[codec]
        if info.rgb:  # an RGB clip stays RGB where the codec holds it (FFV1), else becomes BT.709 Y'CbCr
            from dataclasses import replace

            if pix_fmt in _RGB_FORMATS:
                pix_fmt = _RGB_FORMATS[pix_fmt]
                info = replace(info, matrix=_RGB_MATRIX, range=2)
            else:
                # keep the curve it was decoded with, now tagged (sRGB = 13) as Y'CbCr has no default of its own
                info = replace(info, matrix=1, pixel_format="", transfer=13 if info.curve == "srgb" else info.transfer)
        if info.hdr and bits < 10:
            raise FormatError(f"{info.curve.upper()} video needs 10 bits; {codec} writes 8: use h265, prores or ffv1")
        self.info, self.pix_fmt = info, pix_fmt
        self.container = av.open(str(path), mode="w")
        w, h = size or (info.width, info.height)
        self.stream = self.container.add_stream(encoder, rate=info.rate)
        cc = self.stream.codec_context
        cc.width, cc.height, cc.pix_fmt = w, h, pix_fmt
        cc.color_primaries, cc.color_trc, cc.colorspace, cc.color_range = (info.primaries, info.transfer,
                                                                           info.matrix, info.range)
        cc.thread_type = "AUTO"  # frame threads where the encoder has them, as ffmpeg's own default
        if encoder == "libx265":
            cc.options = {"x265-params": x265_params(w, h)}
        self.count = self.encoded = 0  # frames written, frames given to the encoder
        self._dts: list = [None]  # the last dts muxed (lenslab.io.video.codecs.mux_video)
        self._thread = self._queue = self._error = self._planes = None
        self.audio_from = audio_from
        self.audio: dict = {}
        if audio_from is not None:  # streams are added before the first packet writes the header
            with _open(audio_from) as src:
                self.audio = {s.index: self.container.add_stream_from_template(s) for s in src.streams.audio}

    #: Y'CbCr frames the exact path fills in turn: one being filled, one waiting, one being encoded
    PLANES_RING = 3

    @property
    def held(self) -> int:
        """How many earlier images a :meth:`write` with ``handover`` may still be reading when it returns: 0 where
        the frame goes to the encoder's planes in the caller's thread (Y'CbCr streams), else 3."""
        return 0 if exact(self.info, self.pix_fmt) else 3

    def write(self, image: np.ndarray, encoded: bool = False, handover: bool = False) -> None:
        """Encode one frame: linear Rec.709 light, or (``encoded``) code values in [0, 1] already in the
        stream's primaries and transfer (a display transform's output).

        Y'CbCr streams: the frame goes to the encoder's planes here, in one compiled pass (without the GIL), into a
        ring of :data:`PLANES_RING` frames (or ``image`` is such a frame, filled by :meth:`rows`); RGB streams and
        HLG: the frame is copied. Either is encoded on a thread of its own, at most one frame behind the caller, so
        the next frame's warp overlaps this one's encoding; an error there is raised by the next :meth:`write` or
        by :meth:`close`. ``handover``: ``image`` (float32 H x W x 3) is the writer's from now on, not copied: the
        writer has read it by the time :attr:`held` more :meth:`write` calls have returned."""
        import queue
        import threading

        self._check()
        if self._thread is None:
            self._queue = queue.Queue(maxsize=1)
            self._thread = threading.Thread(target=self._encode_loop, daemon=True, name="lenslab-encode")
            self._thread.start()
        if isinstance(image, np.ndarray) and exact(self.info, self.pix_fmt):  # to the encoder's planes, here
            fill = self.rows(encoded)
            fill(image, slice(0, image.shape[0]))
            image = fill.finish(image)
        if not isinstance(image, np.ndarray):  # a Y'CbCr frame of rows()
            self._queue.put((image, encoded))
            self.count += 1
            return
        self._queue.put((image if handover else np.array(image[..., :3], dtype=np.float32, copy=True), encoded))
        self.count += 1

    def rows(self, encoded: bool = False) -> RowsToYCbCr | None:
        """The next frame's Y'CbCr planes to fill rows at a time (a warp's ``on_band``), then :meth:`write` its
        ``finish``; None where the stream takes RGB (RGB streams, HLG: swscale's path)."""
        if not exact(self.info, self.pix_fmt):
            return None
        # reused in turn: an encoder that still holds one makes PyAV give it new memory (make_writable)
        ring, slot, cc = self._planes or [None] * self.PLANES_RING, self.count % self.PLANES_RING, self.stream.codec_context
        self._planes, ring[slot] = ring, ycbcr_frame(cc.width, cc.height, self.pix_fmt, ring[slot])
        return RowsToYCbCr(self.info, self.pix_fmt, encoded, ring[slot])

    def _encode_loop(self) -> None:
        while True:
            item = self._queue.get()
            if item is None:
                return
            if self._error is None:
                try:
                    self._encode(*item)
                except BaseException as exc:  # raised in the caller's thread
                    self._error = exc

    def _check(self) -> None:
        if self._error is not None:
            error, self._error = self._error, None
            raise error

    def _stop(self) -> None:
        if self._thread is not None:
            self._queue.put(None)
            self._thread.join()
            self._thread = None

    def _encode(self, image, encoded: bool) -> None:
        if isinstance(image, np.ndarray):  # RGB streams, HLG: swscale's path, here
            frame = self._swscale(_av(), image, encoded)
        else:  # the encoder's planes already (write)
            frame = image
        # tags on the frame itself (reformat's dst_color_trc would make FFmpeg convert the pixels too)
        frame.color_trc, frame.color_primaries = self.info.transfer, self.info.primaries
        frame.pts = self.encoded  # in the encoder's time base, 1 / rate
        self.encoded += 1
        mux_video(self.container, self.stream.encode(frame), self._dts)  # (an undefined dts repaired)

    def _swscale(self, av, image: np.ndarray, encoded: bool):
        """Linear (or ``encoded``) frame -> 16-bit codes -> swscale's matrix and range: RGB streams, HLG."""
        codes = linear_to_codes16(image, self.info, encoded)
        frame = av.VideoFrame.from_ndarray(codes, format="rgb48le")
        if self.info.rgb:
            frame = frame.reformat(format=self.pix_fmt)
        else:  # swscale's matrix and range, on threads
            frame = frame.reformat(format=self.pix_fmt, dst_colorspace=_SWS.get(self.info.matrix, "itu709"),
                                   src_color_range="JPEG", dst_color_range=_range(self.info), threads=_THREADS)
        return frame

    def close(self) -> None:
        self._stop()
        self._check()
        mux_video(self.container, self.stream.encode(), self._dts)
        if self.audio_from is not None:
            self._copy_audio()
        self.container.close()

    def _copy_audio(self) -> None:
        if not self.audio:
            return
        with _open(self.audio_from) as src:
            for packet in (p for p in src.demux([s for s in src.streams.audio]) if p.dts is not None):
                packet.stream = self.audio[packet.stream.index]
                self.container.mux(packet)

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if kind is None:
            self.close()
        else:
            self._stop()
            self.container.close()
