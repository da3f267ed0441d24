"""``lenslab convert clip.mp4 -o clip2.mp4``: the whole clip converted keeps the input's audio, its packets
copied as ``lenslab warp`` copies them (the same count, bytes and duration as PyAV reads them from the clip
ffmpeg made); part of it (``--frames``) leaves the audio out, with a note."""

from __future__ import annotations

import shutil
import subprocess

import pytest

av = pytest.importorskip("av")
if shutil.which("ffmpeg") is None:
    pytest.skip("ffmpeg (the command) makes the clip", allow_module_level=True)

from lenslab.cli.main import main  # noqa: E402


def _clip(path):
    """Eight 64x32 frames at 8 fps with one second of a 440 Hz tone (AAC), made by ffmpeg."""
    subprocess.run(["ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=size=64x32:rate=8:duration=1",
                    "-f", "lavfi", "-i", "sine=frequency=440:duration=1", "-c:v", "libx264", "-pix_fmt",
                    "yuv420p", "-c:a", "aac", "-shortest", str(path)], check=True)
    return path


def _audio(path):
    """(packet bytes, stream duration in seconds) of the first audio stream, as PyAV reads them."""
    with av.open(str(path)) as c:
        if not c.streams.audio:
            return None
        s = c.streams.audio[0]
        packets = [bytes(p) for p in c.demux(s) if p.size]
        return packets, float(s.duration * s.time_base) if s.duration else None, s.codec_context.sample_rate


def test_whole_clip_keeps_its_audio(tmp_path):
    src = _clip(tmp_path / "clip.mp4")
    dst = tmp_path / "clip2.mp4"
    assert main(["convert", str(src), "-o", str(dst), "-q"]) == 0
    want, got = _audio(src), _audio(dst)
    assert want is not None and len(want[0]) > 10
    assert got is not None, "the converted clip has no audio stream"
    assert got[0] == want[0]  # every packet, byte for byte
    assert got[2] == want[2] == 44100  # ffmpeg's sine source: 44100 Hz
    if want[1] is not None and got[1] is not None:  # one AAC frame (1024 samples) of muxer padding at most
        assert abs(got[1] - want[1]) <= 1024 / 44100


def test_part_of_a_clip_leaves_the_audio_out_with_a_note(tmp_path, capsys):
    src = _clip(tmp_path / "clip.mp4")
    dst = tmp_path / "part.mp4"
    assert main(["convert", str(src), "-o", str(dst), "--frames", "2:5", "-q"]) == 0
    assert _audio(dst) is None
    assert "audio was left out" in capsys.readouterr().err
