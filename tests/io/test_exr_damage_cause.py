"""A damaged EXR gets one cause, the first line OpenEXR itself prints about the file, whether it is read
alone or while other reads are under way (a batch on threads), and the cause is cut only after whole
words. The expected words are OpenEXR's own, from a separate Python process that reads the file."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import lenslab
from lenslab.cli.main import main
from lenslab.errors import FormatError, cause
from lenslab.library_output import quiet_library

OpenEXR = pytest.importorskip("OpenEXR")

#: OpenEXR's whole-file read, in a process of its own: what the library prints and raises
READ = ("import sys, OpenEXR\ntry:\n    OpenEXR.File(sys.argv[1], separate_channels=True).parts[0].channels\n"
        "except Exception as exc:\n    print('RAISED', exc)\n")


def openexr_says(path) -> tuple[list[str], str]:
    run = subprocess.run([sys.executable, "-c", READ, str(path)], capture_output=True, text=True, cwd=path.parent)
    return run.stderr.splitlines(), run.stdout


def first_chunk(data: bytes) -> int:
    """Where the first chunk's pixel data start: after the header (name, type, size, value up to an empty
    name), the offset table's first entry plus the chunk's 8-byte leader (OpenEXR's file layout)."""
    pos = 8
    while data[pos] != 0:
        pos = data.index(b"\0", data.index(b"\0", pos) + 1) + 1
        pos += 4 + int(np.frombuffer(data[pos:pos + 4], "<i4")[0])
    return int(np.frombuffer(data[pos + 1:pos + 9], "<u8")[0]) + 8


@pytest.fixture
def huffman(tmp_path):
    """A PIZ file whose first chunk's Huffman table starts past its end."""
    rng = np.random.default_rng(1)
    a = rng.uniform(0, 1, (64, 64)).astype(np.float16)
    path = tmp_path / "huffman.exr"
    OpenEXR.File({"compression": OpenEXR.PIZ_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"R": a, "G": a, "B": a}).write(str(path))
    data = bytearray(path.read_bytes())
    at = first_chunk(bytes(data))
    low, high = np.frombuffer(bytes(data[at:at + 4]), "<u2")  # PIZ: the bitmap's first and last byte index
    # after the bitmap, the Huffman data's length (int32) and its table's first code (int32): make that
    # code 4096 larger, past the table's end
    data[at + 4 + (int(high) - int(low) + 1) + 4 + 1] ^= 0x10
    path.write_bytes(bytes(data))
    return path


def message(path) -> str:
    with pytest.raises(FormatError) as caught:
        lenslab.read(path)
    return str(caught.value)


def test_the_cause_is_openexr_first_line_alone_and_beside_other_reads(huffman):
    printed, _ = openexr_says(huffman)
    first = re.sub(r"^[^:]*: \((EXR_ERR_\w+)\) ", r"\1: ", printed[0])
    assert "Huffman" in first
    alone = message(huffman)
    with quiet_library():  # another read under way (a batch's other thread): the capture is shared
        beside = message(huffman)
    assert alone == beside
    assert f"({first})" in alone


def test_a_batch_on_threads_gives_each_copy_the_same_cause(huffman, tmp_path, capsys):
    folder = tmp_path / "batch"
    folder.mkdir()
    for i in range(6):
        shutil.copy(huffman, folder / f"copy{i}.exr")
    alone = message(huffman).split(": ", 1)[1]
    assert main(["convert", str(folder), "--to", "pfm", "-o", str(tmp_path / "out"), "--jobs", "3", "-q"]) == 1
    errors = [ln for ln in capsys.readouterr().err.splitlines() if ": error: " in ln]
    assert len(errors) == 6
    assert {ln.split(".exr: ", 1)[1] for ln in errors} == {alone}


def test_a_truncated_tiled_file_is_described_in_whole_words(shared_data, tmp_path):
    data = (shared_data / "formats" / "openexr-images" / "Tiles" / "GoldenGate.exr").read_bytes()
    cut = tmp_path / "gg.exr"
    cut.write_bytes(data[:len(data) // 2])
    _, raised = openexr_says(cut)
    theirs = raised.split("RAISED", 1)[1].strip() or "corrupt chunk table"
    ours = message(cut)
    why = ours[ours.index("(") + 1:ours.rindex(")")]
    words = why.removesuffix("...").replace(",", " ").split()
    library = set(theirs.replace(",", " ").split()) | set(
        "Unable to use generic API to read with (partially?) corrupt chunk table part 0".split())
    assert "corrupt chunk table" in why and set(words) <= library, why  # every word whole, none cut
    assert "gg.exr," not in why  # the file is named once, at the start of the line


def test_cause_cuts_after_a_whole_word():
    text = "Unable to use generic API to read with (partially?) corrupt chunk table in gg.exr, part 0"
    assert cause(RuntimeError(text), 80) == "Unable to use generic API to read with (partially?) corrupt chunk table in..."
    assert cause(RuntimeError("short"), 80) == "short"
