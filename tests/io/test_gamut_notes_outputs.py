"""The note on a wide-gamut file's colours outside the sRGB gamut counts the pixels of what was written: a warp's
note counts the warped image's pixels and names it (not the input's, which may have four times as many), and a
clip made of wide-gamut frames gets one note for the clip (pixels and frames), not one per frame.

Outside values: which pixels lie outside the sRGB gamut is colour-science's answer in float64 (its sRGB decoding
and its matrix from Display P3 to BT.709), on codes whose pixels near the gamut's edge were made grey
(``tests/io/test_wide_gamut_notes.py``, whose helpers write the files: Pillow's PNG, lenslab's Display P3
profile or a cICP chunk). The pixel and frame totals are counted here from the sizes written.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

pytest.importorskip("colour")
from PIL import Image  # noqa: E402

from tests.io.test_wide_gamut_notes import _codes, _linear_709, _notes, _write  # noqa: E402

NOTE = "hold colours outside the sRGB gamut"


def _outside(codes: np.ndarray, name: str = "display-p3") -> int:
    """colour-science's count: pixels with a negative component in linear BT.709."""
    return int((_linear_709(codes, name).min(axis=-1) < 0).sum())


def test_a_warp_counts_the_pixels_of_the_warped_image_and_names_it(tmp_path, capsys):
    """A 112 x 80 Display P3 panorama of 2 x 2 blocks of one colour, warped to a 56 x 40 panorama with the
    nearest filter: each output pixel's centre falls in the middle of one block (x_in = 2 x_out + 0.5), so the
    output holds each block's colour once, and colour-science's count on the 56 x 40 codes is the output's."""
    codes = _codes("display-p3")  # 40 x 56
    blocks = np.kron(codes, np.ones((2, 2, 1), np.uint8))
    src, out = tmp_path / "p3.png", tmp_path / "srgb.png"
    _write(src, blocks, "display-p3")
    outside = _outside(codes)
    assert 0 < outside < codes.shape[0] * codes.shape[1]
    assert main(["warp", str(src), "--from", "equirect", "--to", "equirect", "--size", "56x40", "--filter",
                 "nearest", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    want = (f"lenslab warp: note: {src}: {outside} of {56 * 40} pixels of the warped image {out} {NOTE} (the file's "
            f"ICC profile 'Display P3'): clipped per channel")
    assert _notes(err) == [want], err
    assert f"of {112 * 80} pixels" not in err  # the input's pixels


def test_a_clip_of_wide_gamut_frames_gets_one_note_with_its_pixels_and_frames(tmp_path, capsys):
    """Four frames written as one H.264 clip: a Display P3 PNG, the same codes mirrored (same count), a cICP
    Display P3 PNG and a plain sRGB PNG (nothing outside). One note for the clip: the three frames' pixels
    outside, of every pixel of the four frames, in 3 of 4 frames, naming both sources of wide primaries."""
    codes = _codes("display-p3")
    mirrored = np.ascontiguousarray(codes[:, ::-1])
    cicp = _codes("cicp-p3")
    frames = [tmp_path / f"f{i}.png" for i in range(4)]
    _write(frames[0], codes, "display-p3")
    _write(frames[1], mirrored, "display-p3")
    _write(frames[2], cicp, "cicp-p3")
    Image.fromarray(codes).save(frames[3])
    outside = _outside(codes) + _outside(mirrored) + _outside(cicp, "cicp-p3")
    clip = tmp_path / "clip.mp4"
    assert main(["convert", *map(str, frames), "--to", "mp4", "-o", str(clip)]) == 0
    err = capsys.readouterr().err
    want = (f"lenslab convert: note: {clip}: {outside} of {4 * 40 * 56} pixels in 3 of 4 frames {NOTE} (the frames' "
            f"ICC profile 'Display P3', cICP primaries P3-D65): clipped per channel")
    assert _notes(err) == [want], err
    assert err.count(NOTE) == 1
