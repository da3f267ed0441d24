"""Damaged and hostile Ultra HDR JPEGs: the base image is read with a one-line note that says why the gain map is
not applied (never a crash or an allocation the file cannot justify), and the input budget counts the gain map."""

from __future__ import annotations

import struct
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import lenslab.io as lio
from lenslab.errors import FormatError
from lenslab.io.budget import BASE_BYTES, BudgetError, admit
from lenslab.io.ldr import GainMapWarning
from lenslab.io.registry import get
from tests.gainmap.files import XMP_SIG, jpeg, ultrahdr

GOOD = {"GainMapMin": 0, "GainMapMax": 2, "HDRCapacityMax": 2}


def _base() -> bytes:
    return jpeg(np.tile(np.arange(0, 256, 8, dtype=np.uint8)[None, :, None], (16, 1, 3)))  # 16 x 32


def _read_noted(path) -> tuple[np.ndarray, str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        image, meta = lio.read(path)
    notes = [str(w.message) for w in caught if issubclass(w.category, GainMapWarning)]
    assert len(notes) == 1 and "\n" not in notes[0], notes
    base, _ = lio.read(f"{path}:sdr")
    np.testing.assert_array_equal(image, base)  # the SDR base image, as ':sdr' reads it
    assert meta["attributes"]["gain_map"] in notes[0] and meta["attributes"]["rendition"].split(":")[0] in (
        "SDR base image", "HDR base image")
    return image, meta["attributes"]["gain_map"]


def _sof_patched(blob: bytes, width: int, height: int) -> bytes:
    at = blob.index(b"\xff\xc0")
    return blob[:at + 5] + struct.pack(">HH", height, width) + blob[at + 9:]


@pytest.mark.parametrize("case, words", [
    ("offset outside", "outside the file"),
    ("offset into the base image", "where no JPEG image starts"),
    ("cut tail", "outside the file"),
    ("gain map cut short", "cut short"),
    ("NaN", "not finite"),
    ("max below min", "below its GainMapMin"),
    ("gamma 0", "Gamma is 0"),
    ("gamma negative", "Gamma is -1"),
    ("gain map larger than the base", "no larger than the base"),
    ("gain map declaring 65000 x 65000", "65000 x 65000"),
    ("version 2", "version '2.0'"),
    ("boost of 2^1000", "beyond 2^64"),
    ("no GainMapMax", "lacks GainMapMax"),
    ("capacities reversed", "are not 0 <= min <= max"),
    ("offset of 5", "beyond +-1"),
    ("base is HDR", "its base image is the HDR rendition (BaseRenditionIsHDR): read as it is"),
    ("grey base, RGB gain map", "base image is grey"),
])
def test_a_hostile_gain_map_leaves_the_base_with_a_note(tmp_path, case, words):
    noise = np.random.default_rng(1).integers(0, 256, (8, 16))
    gain, meta, shift = jpeg(noise), dict(GOOD), 0
    if case == "offset outside":
        shift = 10 ** 6
    elif case == "offset into the base image":
        shift = -300
    elif case == "NaN":
        meta["GainMapMax"] = "nan"
    elif case == "max below min":
        meta.update(GainMapMin=1.5, GainMapMax=0.5)
    elif case == "gamma 0":
        meta["Gamma"] = 0
    elif case == "gamma negative":
        meta["Gamma"] = -1
    elif case == "gain map larger than the base":
        gain = jpeg(np.full((32, 64), 128))
    elif case == "gain map declaring 65000 x 65000":
        gain = _sof_patched(gain, 65000, 65000)
    elif case == "version 2":
        meta["Version"] = "2.0"
    elif case == "boost of 2^1000":
        meta["GainMapMax"] = 1000
    elif case == "no GainMapMax":
        del meta["GainMapMax"]
    elif case == "capacities reversed":
        meta.update(HDRCapacityMin=2, HDRCapacityMax=1)
    elif case == "offset of 5":
        meta["OffsetSDR"] = 5
    elif case == "base is HDR":
        meta["BaseRenditionIsHDR"] = "True"
    elif case == "grey base, RGB gain map":
        gain = jpeg(np.stack([noise] * 3, axis=2))
    elif case == "gain map cut short":
        gain = gain[:-40]  # within its scan: the last 40 bytes of its coded data and its end-of-image marker
    base = jpeg(np.full((16, 32), 77)) if case == "grey base, RGB gain map" else _base()
    blob = ultrahdr(base, gain, meta, offset_shift=shift)
    if case == "cut tail":
        blob = blob[:-40]
    path = tmp_path / "hostile.jpg"
    path.write_bytes(blob)
    _, note = _read_noted(path)
    assert words in note and ("this is the SDR base image" in note or case == "base is HDR")
    declared = admit(path, get("jpg"))
    if case in ("gain map larger than the base", "gain map declaring 65000 x 65000"):
        assert declared.extra_bytes == 0  # never decoded, so not counted


def test_a_damaged_mpf_index_and_damaged_xmp_are_notes(tmp_path):
    blob = ultrahdr(_base(), jpeg(np.full((8, 16), 128)), GOOD)
    at = blob.index(b"MPF\x00") + 4
    path = tmp_path / "mpf.jpg"
    path.write_bytes(blob[:at] + b"XX*\x00" + blob[at + 4:])
    assert "no TIFF header" in _read_noted(path)[1]
    xmp_at = blob.rindex(XMP_SIG) + len(XMP_SIG)
    path.write_bytes(blob[:xmp_at] + b"<x:xmpmeta" + blob[xmp_at + 10:].replace(b"</x:xmpmeta>", b"</x:xmpmetb>"))
    assert "cannot be parsed" in _read_noted(path)[1]


def test_the_budget_counts_the_gain_maps_pixels(tmp_path):
    path = tmp_path / "counted.jpg"
    path.write_bytes(ultrahdr(_base(), jpeg(np.full((10, 16, 3), 90)), GOOD))
    assert admit(path, get("jpg")).extra_bytes == 16 * 10 * 3 * 4  # float32 RGB of the 16 x 10 gain map


def test_a_gain_map_that_tips_a_small_file_past_the_budget_is_refused(tmp_path):
    """A flat 4096 x 2048 RGB base decodes to exactly BASE_BYTES (96 MiB), which any file may decode to; its
    1024 x 512 gain map adds 2 MiB of float32, beyond what a file this small (under 192 KiB: 96 MiB / 512, the
    most a small file's bytes may buy) may decode to: refused before any pixel is decoded."""
    assert 4096 * 2048 * 3 * 4 == BASE_BYTES == 96 << 20
    base = jpeg(np.full((2048, 4096, 3), 100), 90, subsampling=2)  # 4:2:0: a flat picture in 131 kB
    alone = tmp_path / "alone.jpg"
    alone.write_bytes(base)
    assert admit(alone, get("jpg")).float_bytes == BASE_BYTES
    path = tmp_path / "tipped.jpg"
    path.write_bytes(ultrahdr(base, jpeg(np.full((512, 1024), 128), 90), GOOD))
    assert path.stat().st_size < BASE_BYTES // 512
    with pytest.raises(BudgetError, match="decompression bomb"):
        lio.read(path)


_GOOD_FILE = ultrahdr(jpeg(np.random.default_rng(2).integers(0, 256, (24, 40, 3))),
                      jpeg(np.random.default_rng(3).integers(0, 256, (12, 20, 3))),
                      {"GainMapMin": [0, 0.1, 0.2], "GainMapMax": [2, 2.5, 3], "Gamma": [1, 2, 0.5],
                       "HDRCapacityMax": 3})


@settings(max_examples=120, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.integers(0, len(_GOOD_FILE) - 1), st.integers(0, 255)), min_size=1, max_size=4),
       st.integers(16, len(_GOOD_FILE)))
def test_any_damage_reads_or_is_refused_in_one_line(tmp_path_factory, changes, keep):
    """Bytes changed anywhere (the MPF index, the XMP, either image) and the file cut anywhere: the read gives a
    finite float32 image or a FormatError, never another exception."""
    blob = bytearray(_GOOD_FILE)
    for at, value in changes:
        blob[at] = value
    path = tmp_path_factory.mktemp("damage") / "d.jpg"
    path.write_bytes(bytes(blob[:keep]))
    attributes = read_or_refused(path)
    # (a change that hits both "hdrgm:" names leaves a plain JPEG: no rendition to name)
    assert attributes is None or attributes.get("rendition", "plain").split(":")[0] in ("HDR", "SDR base image",
                                                                                         "plain")


def read_or_refused(path) -> dict | None:
    """The attributes of a damaged file read as a finite float32 image, or None where it is refused with a
    FormatError of one line; any other exception fails."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            image, meta = lio.read(path)
        except FormatError as exc:
            assert "\n" not in str(exc)
            return None
    assert image.dtype == np.float32 and np.isfinite(image).all()
    return meta["attributes"]
