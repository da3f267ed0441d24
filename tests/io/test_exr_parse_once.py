"""One read of an EXR parses its header once with lenslab's own parser (the byte budget's reading is
given to the reader, which checks the chunks and takes the stored types from it; OpenEXR's own parse
stays) and decodes its pixels once, extra channels (depth, ids, other layers) included. Expected values:
OpenEXR's reading of the same header and pixels."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.exr import chunks

H, W = 45, 37


def _file(path, tiled=False, multipart=False, data=((0, 0), (W - 1, H - 1)), compression="PIZ"):
    """R, G, B half, Z float, id uint; ``multipart``: that part second, after a small Y part."""
    (x0, y0), (x1, y1) = data
    h, w = y1 - y0 + 1, x1 - x0 + 1
    rng = np.random.default_rng(7)
    chans = {c: rng.random((h, w)).astype(np.float16) for c in "RGB"}
    chans["Z"] = rng.uniform(1, 100, (h, w)).astype(np.float32)
    chans["id"] = rng.integers(0, 2 ** 31, (h, w), dtype=np.uint32)
    header = {"compression": getattr(OpenEXR, f"{compression}_COMPRESSION"), "dataWindow": data,
              "displayWindow": ((0, 0), (W - 1, H - 1)),
              "type": OpenEXR.tiledimage if tiled else OpenEXR.scanlineimage}
    if tiled:
        tiles = OpenEXR.TileDescription()
        tiles.xSize, tiles.ySize, tiles.mode = 16, 8, OpenEXR.ONE_LEVEL
        header["tiles"] = tiles
    if multipart:
        other = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "name": "second",
                 "dataWindow": ((0, 0), (10, 8)), "displayWindow": header["displayWindow"]}
        # the rich part second: it is read by OpenEXR's whole-file read (the band reader takes part 0 only)
        OpenEXR.File([OpenEXR.Part(other, {"Y": rng.random((9, 11)).astype(np.float32)}),
                      OpenEXR.Part({**header, "name": "rich"}, chans)]).write(str(path))
    else:
        OpenEXR.File(header, chans).write(str(path))
    return path


@pytest.fixture
def parses(monkeypatch):
    calls = []
    parse = chunks.parse_header
    monkeypatch.setattr(chunks, "parse_header", lambda path: calls.append(str(path)) or parse(path))
    return calls


@pytest.fixture
def decodes(monkeypatch):
    """Every opening of a file by OpenEXR that decodes pixels (the band reader's scanline interface, the
    whole-file read), and every header-only opening."""
    calls = []
    file_, input_ = OpenEXR.File, OpenEXR.InputFile

    def counted_file(*a, **k):
        if isinstance(a[0], str):
            calls.append("header" if k.get("header_only") else "pixels")
        return file_(*a, **k)

    def counted_input(*a, **k):
        calls.append("pixels")
        return input_(*a, **k)

    monkeypatch.setattr(OpenEXR, "File", counted_file)
    monkeypatch.setattr(OpenEXR, "InputFile", counted_input)
    return calls


@pytest.mark.parametrize("kind", ["scanline", "tiled", "multipart"])
def test_a_read_parses_the_header_once_and_the_parse_is_openexrs_header(tmp_path, parses, kind):
    path = _file(tmp_path / "f.exr", tiled=kind == "tiled", multipart=kind == "multipart",
                 data=((3, 2), (W - 5, H - 1)))
    lio.read(f"{path}:rich" if kind == "multipart" else path)
    assert parses == [str(path)]  # once: the budget's parse, given to the reader
    layout = chunks.parse_header(path)
    theirs = OpenEXR.File(str(path), header_only=True).parts
    assert len(layout.parts) == len(theirs) and layout.multipart == (kind == "multipart")
    for mine, part in zip(layout.parts, theirs):
        h = part.header
        for name in ("dataWindow", "displayWindow"):
            assert mine[name] == tuple(int(v) for corner in h[name] for v in corner)
        assert mine["channel_names"] == [c.name for c in h["channels"]]
        assert mine["compression"] == h["compression"].value
        assert mine["tiled"] == (h["type"] == OpenEXR.tiledimage)
        if mine["tiled"]:
            assert mine["tiles"] == (h["tiles"].xSize, h["tiles"].ySize, h["tiles"].mode.value)
    # the stored types: what OpenEXR's whole read gives each channel
    pixels = OpenEXR.File(str(path), separate_channels=True).parts[0].channels
    kinds = {"float16": "HALF", "float32": "FLOAT", "uint32": "UINT"}
    assert layout.parts[0]["channel_types"] == {n: kinds[str(c.pixels.dtype)] for n, c in pixels.items()}


def _theirs(path, part):
    return OpenEXR.File(str(path), separate_channels=True).parts[part].channels


@pytest.mark.parametrize("multipart", [False, True])
def test_convert_exr_to_exr_parses_once_and_decodes_once_with_extra_channels(tmp_path, parses, decodes, multipart):
    from lenslab.jobs.convert import ConvertJob

    src = _file(tmp_path / "in.exr", multipart=multipart, data=((2, 1), (W - 3, H - 4)))
    out = tmp_path / "out.exr"
    ConvertJob(to="exr").run(f"{src}:rich" if multipart else str(src), str(out))
    assert parses == [str(src)]
    # one decoding of the pixels (the image and its extra channels together); OpenEXR's header parse stays
    assert sorted(decodes) == ["header", "pixels"]
    index = 1 if multipart else 0
    theirs, written = _theirs(src, index), _theirs(out, 0)
    for name in ("Z", "id", "R", "G", "B"):  # every channel as stored, where it was stored
        assert written[name].pixels.dtype == theirs[name].pixels.dtype
        assert np.array_equal(written[name].pixels, theirs[name].pixels)


@pytest.mark.parametrize("multipart", [False, True])
def test_extra_planes_are_placed_in_the_display_window_as_the_image_is(tmp_path, multipart):
    (x0, y0), (x1, y1) = (4, 3), (W - 2, H - 6)
    src = _file(tmp_path / "in.exr", multipart=multipart, data=((x0, y0), (x1, y1)))
    image, meta = lio.read(f"{src}:rich" if multipart else src, extra_channels=True)
    theirs = _theirs(src, 1 if multipart else 0)
    assert image.shape[:2] == (H, W) and sorted(meta["extra_planes"]) == ["Z", "id"]
    for name, plane in meta["extra_planes"].items():
        expected = np.zeros((H, W), theirs[name].pixels.dtype)  # outside the data window: 0, as for the image
        expected[y0:y1 + 1, x0:x1 + 1] = theirs[name].pixels
        assert plane.dtype == expected.dtype and np.array_equal(plane, expected)
