"""What a new user meets on a first walk through the commands: options that cannot apply are usage errors
(exit 2, one line, before any work, no output made), every error line has the same form, and a file's notes
are printed as notes by every command."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.fixture
def pano(tmp_path):
    p = tmp_path / "pano.exr"
    write(p, np.full((16, 32, 3), 0.5, np.float32))
    return p


def one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("filt", ["nearest", "bicubic", "lanczos"])
def test_a_filter_with_antialias_is_a_usage_error(pano, tmp_path, capsys, filt):
    out = tmp_path / "out.exr"
    rc = main(["warp", str(pano), "-o", str(out), "--to", "perspective:fov=30", "--size", "8x8",
               "--filter", filt, "--antialias"])
    line = one_line(capsys)
    assert rc == 2
    assert line == (f"lenslab warp: error: --filter {filt} does nothing with --antialias: the footprint filter "
                    "replaces it (it averages the bilinear source over each pixel's footprint); give one")
    assert not out.exists()


def test_the_default_filter_with_antialias_warps(pano, tmp_path, capsys):
    out = tmp_path / "out.exr"
    rc = main(["warp", str(pano), "-o", str(out), "--to", "perspective:fov=30", "--size", "8x8", "--antialias", "-q"])
    assert rc == 0 and out.exists()


def test_the_python_api_refuses_a_filter_with_antialias_too():
    import lenslab
    from lenslab.errors import WarpError
    from lenslab.warp import warp_with_map

    pano = np.full((16, 32, 3), 0.5, np.float32)
    src = lenslab.Camera.from_spec("equirect", (32, 16))
    dst = lenslab.Camera.from_spec("perspective:fov=30", (8, 8))
    with pytest.raises(WarpError, match="filter bicubic does nothing with antialias: the footprint filter"):
        lenslab.warp(pano, src, dst, filter="bicubic", antialias=True)
    xy = np.stack(np.meshgrid(np.arange(4) + 0.5, np.arange(4) + 0.5), axis=-1)
    with pytest.raises(WarpError, match="filter nearest does nothing with antialias"):
        warp_with_map(pano, xy, filter="nearest", antialias=True)
    # the guide's example: the footprint filter on its own
    image, alpha = lenslab.warp(pano, src, dst, antialias=True)
    np.testing.assert_allclose(image, 0.5, rtol=1e-3)  # a constant source stays constant (half-float input)


def test_the_display_named_in_the_help_picks_that_display(pano, tmp_path, capsys):
    """``--display 'Display P3'`` (the --help example): the name before " - " wins over 'Display P3 HDR - Display'.
    The display's names are OpenColorIO's own, from its built-in config."""
    import PyOpenColorIO as OCIO

    from lenslab.io.ocio import load_config, resolve

    config = load_config(None)
    names = list(config.getDisplays())
    assert {"Display P3 - Display", "Display P3 HDR - Display"} <= set(names)
    assert resolve(config, "Display P3", None)[0] == "Display P3 - Display"
    assert resolve(config, "display p3 hdr", None)[0] == "Display P3 HDR - Display"
    assert resolve(config, "Display P3 - Display", None)[0] == "Display P3 - Display"
    out = tmp_path / "p3.png"
    assert main(["tonemap", str(pano), "-o", str(out), "--display", "Display P3", "-q"]) == 0 and out.exists()
    capsys.readouterr()
    rc = main(["tonemap", str(pano), "-o", str(tmp_path / "x.png"), "--display", "P3"])
    line = one_line(capsys)
    assert rc == 2 and line.startswith("lenslab tonemap: error: display 'P3' matches several of the config's: "
                                       "Display P3 - Display; Display P3 HDR - Display;")
    assert OCIO.GetVersion()  # the names above are those of the OpenColorIO installed


def multipart_exr(path):
    """A two-part EXR written by OpenEXR itself (not by lenslab)."""
    OpenEXR = pytest.importorskip("OpenEXR")
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    a = np.full((4, 8), 0.5, np.float32)
    parts = [OpenEXR.Part({**h, "name": "beauty"}, {"R": a, "G": a, "B": a}, "beauty"),
             OpenEXR.Part({**h, "name": "depth"}, {"Z": 7 * a}, "depth")]
    OpenEXR.File(parts).write(str(path))
    return path


@pytest.mark.parametrize("command", [["tonemap", "{m}", "-o", "{d}/t.png", "-q"],  # (info lists the parts instead)
                                     ["diff", "{m}", "{m}", "-q"],
                                     ["warp", "{m}", "-o", "{d}/w.exr", "--to", "fisheye", "--size", "8x8", "-q"],
                                     ["convert", "{m}", "--to", "pfm", "-o", "{d}/c.pfm", "-q"]])
def test_the_multi_part_note_is_one_note_line_in_every_command(tmp_path, capsys, command):
    m = multipart_exr(tmp_path / "m.exr")
    rc = main([a.format(m=m, d=tmp_path) for a in command])
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if "has 2 parts" in line]
    assert rc == 0
    assert notes == [f"lenslab {command[0]}: note: {m}: has 2 parts (0: 'beauty', 1: 'depth'); read part 0 "
                     "('beauty') only: the other part is neither read nor written; pick another as m.exr:NAME or "
                     "m.exr:INDEX"], err
    assert "MultiPartWarning" not in err and "warnings.warn" not in err and ".py:" not in err


@pytest.mark.parametrize("command", [["warp", "{n}", "-o", "{d}/x.exr", "--to", "fisheye"],
                                     ["convert", "{n}", "--to", "png", "-o", "{d}/x.png"],
                                     ["tonemap", "{n}", "-o", "{d}/x.png"], ["tonemap", "{n}", "{n}2", "-o", "{d}/o"],
                                     ["info", "{n}"], ["diff", "{n}", "{n}"]])
def test_a_missing_input_is_one_error_line_of_the_same_form_in_every_command(tmp_path, capsys, command):
    n = tmp_path / "nothere.exr"
    rc = main([a.format(n=n, d=tmp_path) for a in command])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == (4 if command[0] == "diff" else 1)  # diff keeps idiff's exit codes: 4, a file not read
    assert err[0] == f"lenslab {command[0]}: error: {n}: no such file or directory", err
    assert all(line.startswith(f"lenslab {command[0]}: error: ") for line in err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing made, not even the output folder


def mpeg_ts(path):
    """A real MPEG transport stream (a format lenslab does not read), written by PyAV (FFmpeg)."""
    av = pytest.importorskip("av")
    with av.open(str(path), "w", format="mpegts") as box:
        stream = box.add_stream("mpeg2video", rate=25)
        stream.width, stream.height, stream.pix_fmt = 16, 16, "yuv420p"
        for i in range(3):
            frame = av.VideoFrame.from_ndarray(np.full((16, 16, 3), 40 * i, np.uint8), format="rgb24")
            for packet in stream.encode(frame):
                box.mux(packet)
        for packet in stream.encode():
            box.mux(packet)
    return path


def test_a_video_warp_of_an_unread_input_names_the_input_as_convert_does(tmp_path, capsys):
    clip = mpeg_ts(tmp_path / "clip.ts")
    assert clip.read_bytes()[0] == 0x47  # MPEG-TS's sync byte: a real transport stream
    out = tmp_path / "fish.mp4"
    rc = main(["warp", str(clip), "-o", str(out), "--to", "fisheye:fov=180", "--size", "8x8"])
    line = one_line(capsys)
    assert rc == 1 and line.startswith(f"lenslab warp: error: {clip}: not a recognised image"), line
    assert "fish.mp4" not in line and not out.exists()
    rc = main(["convert", str(clip), "--to", "mp4", "-o", str(out)])
    assert rc == 1 and one_line(capsys).split(": error: ")[1] == line.split(": error: ")[1]


def test_a_still_image_warped_to_a_video_name_is_a_usage_error(pano, tmp_path, capsys):
    out = tmp_path / "fish.mp4"
    rc = main(["warp", str(pano), "-o", str(out), "--to", "fisheye:fov=180", "--size", "8x8"])
    assert rc == 2 and one_line(capsys) == (f"lenslab warp: error: {pano} is a still image and -o {out} a video: "
                                            "warp it to an image file (e.g. .exr), or give a video input")
    assert not out.exists()


PQ_JPEG = "Rec.2100-PQ: an HDR display needs 16-bit samples; JPEG holds 8: write PNG"
RGB_PGM = "PGM holds 1 channel(s); this image has 3: write PPM, or keep one channel"


@pytest.mark.parametrize("command,message", [
    (["warp", "{p}", "-o", "{d}/w.jpg", "--to", "fisheye", "--size", "8x8", "--display", "Rec.2100-PQ"], PQ_JPEG),
    (["convert", "{p}", "--to", "jpg", "-o", "{d}/w.jpg", "--display", "Rec.2100-PQ"], PQ_JPEG),
    (["tonemap", "{p}", "-o", "{d}/w.jpg", "--display", "Rec.2100-PQ"], PQ_JPEG),
    (["tonemap", "{p}", "-o", "{d}/w.png", "--display", "Rec.2100-PQ", "--bits", "8"],
     "Rec.2100-PQ: an HDR display needs 16-bit samples; drop --bits 8"),
    (["warp", "{p}", "-o", "{d}/w.pgm", "--to", "fisheye", "--size", "8x8", "--display", "sRGB"],
     "sRGB: a display's code values are RGB; PGM holds 1 channel(s): write PPM, PNG or TIFF"),
    (["warp", "{p}", "-o", "{d}/w.pgm", "--to", "fisheye", "--size", "8x8"], "{p}: " + RGB_PGM),
    (["convert", "{p}", "--to", "pgm", "-o", "{d}/w.pgm"], "{p}: " + RGB_PGM),
    (["tonemap", "{p}", "-o", "{d}/w.pgm"], "{p}: " + RGB_PGM),
    (["tonemap", "{p}", "{p}", "-o", "{d}/o", "--format", "pgm"], "{p}: " + RGB_PGM),
])
def test_an_output_that_cannot_hold_what_is_asked_is_refused_before_any_work(pano, tmp_path, capsys, monkeypatch,
                                                                             command, message):
    import lenslab.io

    def no_read(*a, **k):
        raise AssertionError("the input was read: the refusal came after work")

    monkeypatch.setattr(lenslab.io, "read", no_read)
    rc = main([a.format(p=pano, d=tmp_path) for a in command])
    assert rc == 2
    assert one_line(capsys) == f"lenslab {command[0]}: error: " + message.format(p=pano)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pano.exr"]


def test_what_the_output_can_hold_still_works(pano, tmp_path):
    """PQ into 16-bit PNG, and one grey channel into PGM (the channel count read from the EXR header,
    as OpenEXR writes it)."""
    OpenEXR = pytest.importorskip("OpenEXR")
    grey = tmp_path / "grey.exr"
    h = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(h, {"Y": np.full((16, 32), 0.5, np.float32)}).write(str(grey))
    assert main(["warp", str(grey), "-o", str(tmp_path / "g.pgm"), "--to", "fisheye", "--size", "8x8", "-q"]) == 0
    assert main(["warp", str(pano), "-o", str(tmp_path / "pq.png"), "--to", "fisheye", "--size", "8x8",
                 "--display", "Rec.2100-PQ", "-q"]) == 0
    assert (tmp_path / "pq.png").read_bytes()[24] == 16  # the IHDR's bit depth (PNG spec, 11.2.2): 16 bits


@pytest.mark.parametrize("command", [["warp", "--to", "fisheye", "--size", "8x8"], ["convert", "--to", "pfm"],
                                     ["tonemap"]])
def test_a_failed_file_of_a_batch_is_an_error_line_of_the_same_form(pano, tmp_path, capsys, command):
    bad = tmp_path / "bad.exr"
    bad.write_bytes(b"v/1\x01" + bytes(60))  # OpenEXR's magic number and a broken header
    rc = main([command[0], str(pano), str(bad), "-o", str(tmp_path / "out"), *command[1:], "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1
    assert [line for line in err if "bad.exr" in line][0].startswith(f"lenslab {command[0]}: error: {bad}: "), err
