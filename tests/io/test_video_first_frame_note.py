"""A clip read as one image (``lenslab tonemap clip.mkv``, ``lenslab diff``) is its first frame, and the command says
so in one note that names the commands taking every frame; a clip of one frame reads without a note. The clips
are made with PyAV and decoded here with colour-science (:mod:`tests.io.ycbcr_oracle`)."""

from __future__ import annotations

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.cli.main import main  # noqa: E402
from tests.io.ycbcr_oracle import decode_codes, write_ffv1  # noqa: E402

W, H = 16, 8


def _clip(path, frames: int) -> list[np.ndarray]:
    write_ffv1(path, [np.full((H, W, 3), 0.2 + 0.25 * i) for i in range(frames)])
    return [colour.models.eotf_BT1886(codes, L_B=0, L_W=1) for codes in decode_codes(path)]


def _notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "first frame" in line]


def test_tonemap_of_a_clip_says_it_took_the_first_frame(tmp_path, capsys):
    want = _clip(tmp_path / "clip.mkv", 3)
    out = tmp_path / "still.png"
    assert main(["tonemap", str(tmp_path / "clip.mkv"), "-o", str(out), "--tone", "clamp", "--no-dither"]) == 0
    assert _notes(capsys.readouterr().err) == [
        f"lenslab tonemap: note: {tmp_path / 'clip.mkv'}: a clip of several frames: its first frame read, as one image "
        "('lenslab convert' and 'lenslab warp' take every frame)"]
    from PIL import Image

    got = colour.models.eotf_sRGB(np.asarray(Image.open(out), np.float64) / 255)
    np.testing.assert_allclose(got, want[0], atol=0.01)  # frame 0 (frame 1 is 0.25 of the code range brighter)


def test_an_mp4_says_its_frame_count(tmp_path, capsys):  # (Matroska gives no count without decoding the clip)
    write_ffv1(tmp_path / "clip.mkv", [np.full((H, W, 3), 0.2 + 0.25 * i) for i in range(3)])
    with av.open(str(tmp_path / "clip.mkv")) as src, av.open(str(tmp_path / "clip.mp4"), "w") as dst:
        s = dst.add_stream("libx264", rate=25)
        s.width, s.height, s.pix_fmt = W, H, "yuv420p"
        for frame in src.decode(video=0):
            for packet in s.encode(frame.reformat(format="yuv420p")):
                dst.mux(packet)
        for packet in s.encode():
            dst.mux(packet)
    with av.open(str(tmp_path / "clip.mp4")) as c:
        assert c.streams.video[0].frames == 3  # the count PyAV reads from the MP4's sample table
    assert main(["diff", str(tmp_path / "clip.mp4"), str(tmp_path / "clip.mp4"), "-q"]) == 0
    notes = _notes(capsys.readouterr().err)
    assert len(notes) == 1 and "a clip of 3 frames: its first frame read" in notes[0], notes  # the same file: once


def test_a_clip_of_one_frame_reads_without_a_note(tmp_path, capsys):
    _clip(tmp_path / "one.mkv", 1)
    assert main(["tonemap", str(tmp_path / "one.mkv"), "-o", str(tmp_path / "still.png")]) == 0
    assert _notes(capsys.readouterr().err) == []
