"""An EXR whose data window lies wholly outside its display window is read, as a compositor shows it, as its display
window: all 0. The command says so in one note (the image would otherwise be silently black) and names
--data-window; an EXR output keeps both windows and needs no note.

Outside values: the file is written with OpenEXR's own binding; the windows in the expected note are those its
header holds, and the image expected is OpenImageIO's reading of the display window (roi_full)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")


def _exr(path, data, display) -> np.ndarray:
    (x0, y0), (x1, y1) = data
    pixels = np.full((y1 - y0 + 1, x1 - x0 + 1, 3), 0.75, np.float16)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "dataWindow": (np.array(data[0], np.int32), np.array(data[1], np.int32)),
              "displayWindow": (np.array(display[0], np.int32), np.array(display[1], np.int32))}
    with OpenEXR.File(header, {"RGB": pixels}) as f:
        f.write(str(path))
    return pixels


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "wholly outside the display window" in line]


def test_a_disjoint_data_window_is_said_once(tmp_path, capsys):
    src = tmp_path / "aside.exr"
    _exr(src, ((0, 0), (7, 3)), ((8, 0), (11, 3)))
    out = tmp_path / "aside.pfm"
    assert main(["convert", str(src), "-o", str(out)]) == 0
    assert _notes(capsys.readouterr().err) == [
        f"lenslab convert: note: {src}: the data window [0, 0, 7, 3] lies wholly outside the display window "
        "[8, 0, 11, 3]: the image (its display window) holds none of the stored pixels, only 0; "
        "'lenslab convert --data-window' writes them"]
    from lenslab.io import read

    got = read(out)[0]
    oiio = pytest.importorskip("OpenImageIO")
    buf = oiio.ImageBuf(str(src))
    want = buf.get_pixels(oiio.FLOAT, buf.roi_full)
    assert got.shape == want.shape == (4, 4, 3)
    np.testing.assert_array_equal(got, want)  # all 0, as OpenImageIO reads the display window
    assert main(["convert", str(src), "-o", str(tmp_path / "data.pfm"), "--data-window"]) == 0
    assert _notes(capsys.readouterr().err) == []
    np.testing.assert_array_equal(read(tmp_path / "data.pfm")[0], 0.75)


@pytest.mark.parametrize("display", [((7, 3), (10, 5)), ((-4, -2), (0, 0)), ((0, 0), (7, 3))])
def test_windows_that_share_a_pixel_give_no_note(tmp_path, capsys, display):
    src = tmp_path / "touch.exr"
    _exr(src, ((0, 0), (7, 3)), display)
    assert main(["convert", str(src), "-o", str(tmp_path / "out.pfm")]) == 0
    assert _notes(capsys.readouterr().err) == []


def test_exr_to_exr_keeps_both_windows_without_a_note(tmp_path, capsys):
    src = tmp_path / "aside.exr"
    _exr(src, ((0, 0), (7, 3)), ((8, 0), (11, 3)))
    assert main(["convert", str(src), "-o", str(tmp_path / "copy.exr")]) == 0
    assert _notes(capsys.readouterr().err) == []
    header = OpenEXR.File(str(tmp_path / "copy.exr")).header()
    assert [list(map(int, v)) for v in header["dataWindow"]] == [[0, 0], [7, 3]]
    assert [list(map(int, v)) for v in header["displayWindow"]] == [[8, 0], [11, 3]]
