"""Every readable format has a probe, and ``lenslab info`` on a file of each format reports the size and
channels an outside library wrote into it and reads back from it.

Parametrized from the format registry (:func:`lenslab.io.registry.formats`): a readable format with no
outside writer below fails here until one is added. The files are written by OpenEXR, tifffile, OpenCV,
PyAV and pillow-heif (never by lenslab), and their size and channels are read back by the same library: OpenEXR's
header, tifffile's page, ``cv2.imread(..., IMREAD_UNCHANGED)``, PyAV's stream and decoded frame, pillow-heif's
image.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io.registry import formats

W, H = 13, 9  # odd and unequal, so a swapped width and height shows


def _exr(path):
    import OpenEXR

    rgba = {c: np.full((H, W), 0.25 * (i + 1), np.float16) for i, c in enumerate("RGBA")}
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, rgba).write(str(path))
    head = OpenEXR.File(str(path), header_only=True).header()
    (x0, y0), (x1, y1) = head["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1), len(head["channels"])


def _tiff(path):
    import tifffile

    tifffile.imwrite(path, np.zeros((H, W, 4), np.uint16), photometric="rgb", extrasamples=["unassalpha"])
    with tifffile.TiffFile(path) as tif:
        h, w, c = tif.pages[0].shape
    return w, h, c


def _opencv(image):
    def make(path):
        import cv2

        assert cv2.imwrite(str(path), image)
        back = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        return back.shape[1], back.shape[0], 1 if back.ndim == 2 else back.shape[2]
    return make


def _video(path):
    import av

    frames = [av.VideoFrame.from_ndarray(np.full((16, 32, 3), v, np.uint8), format="rgb24") for v in (0, 90)]
    with av.open(str(path), "w") as c:
        s = c.add_stream("ffv1", rate=25)
        s.width, s.height, s.pix_fmt = 32, 16, "yuv420p"
        packets = [p for f in frames for p in s.encode(f)] + list(s.encode())
        c.mux(packets)
    with av.open(str(path)) as c:
        frame = next(c.decode(video=0))
        return frame.width, frame.height, frame.to_ndarray(format="rgb24").shape[2]


def _heif(path):
    import pillow_heif

    pillow_heif.from_bytes("RGBA", (W, H), np.zeros((H, W, 4), np.uint8).tobytes()).save(str(path), quality=90)
    back = pillow_heif.open_heif(str(path))
    return back.size[0], back.size[1], np.asarray(back).shape[2]


#: format name -> (file extension, writer returning the outside library's (width, height, channels))
MAKERS = {
    "exr": (".exr", _exr),
    "tiff": (".tif", _tiff),
    "png": (".png", _opencv(np.zeros((H, W, 4), np.uint8))),
    "jpg": (".jpg", _opencv(np.full((H, W, 3), 128, np.uint8))),
    "ppm": (".ppm", _opencv(np.zeros((H, W, 3), np.uint8))),
    "pgm": (".pgm", _opencv(np.zeros((H, W), np.uint16))),
    "pbm": (".pbm", _opencv((np.arange(H * W).reshape(H, W) % 2 * 255).astype(np.uint8))),
    "pfm": (".pfm", _opencv(np.ones((H, W, 3), np.float32))),
    "hdr": (".hdr", _opencv(np.ones((H, W, 3), np.float32))),
    "video": (".mkv", _video),
    "heif": (".heic", _heif),
}
READABLE = [f.name for f in formats().values() if f.readable]


def _info(capsys, path) -> dict:
    assert main(["info", "--json", str(path)]) == 0
    (d,) = json.loads(capsys.readouterr().out)
    return d


@pytest.mark.parametrize("name", READABLE)
def test_every_readable_format_has_a_probe_and_an_outside_writer_here(name):
    assert callable(formats()[name].probe), f"format {name} has no probe hook (Format.probe)"
    assert name in MAKERS, f"format {name}: add an outside library's writer to MAKERS"


@pytest.mark.parametrize("name", READABLE)
def test_info_reports_the_size_and_channels_the_outside_library_reads(tmp_path, capsys, name):
    ext, make = MAKERS[name]
    path = tmp_path / f"x{ext}"
    width, height, channels = make(path)
    d = _info(capsys, path)
    assert d["format"] == name
    if formats()[name].kind == "video":
        import av

        (stream,) = [s for s in d["video"]["streams"] if s["kind"] == "video"]
        assert (stream["width"], stream["height"]) == (width, height)
        # the stream's pixel format holds as many colour components as PyAV's decoded RGB frame
        assert len(av.VideoFormat(stream["pixel_format"]).components) == channels
        return
    assert (d["width"], d["height"], len(d["channels"])) == (width, height, channels)
    structure = d["structure"]
    assert structure["file_bytes"] == os.path.getsize(path)
    if name == "exr":
        (part,) = structure["parts"]
        assert part["data_window"] == [0, 0, W - 1, H - 1] and part["compression"] == "zip"
        assert sorted(c["name"] for c in part["channels"]) == ["A", "B", "G", "R"]
        assert {c["type"] for c in part["channels"]} == {"half"}
    elif name == "tiff":
        (page,) = structure["pages"]
        assert page["shape"] == [height, width, channels] and page["dtype"] == "uint16"
    elif name == "hdr":  # the resolution line as the file spells it (Radiance's standard orientation)
        assert f"-Y {height} +X {width}".encode() in path.read_bytes()[:200]
        assert structure["resolution"] == f"-Y {height} +X {width}"
    else:  # one image and its header, which the reader reports: info shows the reader's attributes
        assert set(structure) == {"file_bytes"}
