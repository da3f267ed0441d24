"""HDR display PNGs carry their encoding in a ``cICP`` chunk (PNG Specification, Third Edition, 11.3.2.6):
checked here by parsing the file's chunks as the specification lays them out, and by OpenImageIO's reader;
read back, a PQ or HLG PNG is linear light by colour-science's EOTFs."""

from __future__ import annotations

import struct
import zlib

import colour
import numpy as np
import pytest

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402


def chunks(path):
    """(type, data) of every chunk, each CRC checked (PNG: 4-byte length, type, data, CRC-32 of type + data)."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, out = 8, []
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert crc == zlib.crc32(kind + body) & 0xFFFFFFFF, kind
        out.append((kind.decode("ascii"), body))
        pos += 12 + length
    return out


def scene():
    rng = np.random.default_rng(0)
    return np.exp2(rng.uniform(-6, 6, (6, 10, 3))).astype(np.float32)


@pytest.mark.parametrize("display, config, transfer", [
    ("rec.2100-pq", None, 16),
    ("rec.2100-hlg", "ocio://studio-config-latest", 18),
])
def test_hdr_display_png_has_the_rec2100_cicp_chunk(tmp_path, display, config, transfer):
    lio.write(tmp_path / "s.exr", scene(), pixel_type="float")
    args = ["convert", str(tmp_path / "s.exr"), "--to", "png", "--display", display, "-o", str(tmp_path / "d.png"),
            "-q"] + (["--ocio", config] if config else [])
    assert main(args) == 0
    found = chunks(tmp_path / "d.png")
    kinds = [k for k, _ in found]
    # the specification: cICP holds colour primaries, transfer, matrix, full-range flag (one byte each) and
    # comes before IDAT; Rec.2100 is BT.2020 primaries 9, PQ 16 or HLG 18, RGB matrix 0, full range 1
    assert kinds[0] == "IHDR" and kinds.count("cICP") == 1 and kinds.index("cICP") < kinds.index("IDAT")
    assert dict(found)["cICP"] == bytes([9, transfer, 0, 1])
    assert found[0][1][8] == 16  # IHDR bit depth: HDR codes need 16 bits

    oiio = pytest.importorskip("OpenImageIO")
    inp = oiio.ImageInput.open(str(tmp_path / "d.png"))
    try:
        spec = inp.spec()
        assert list(spec.getattribute("CICP")) == [9, transfer, 0, 1]  # OpenImageIO's reading of the chunk
        theirs = inp.read_image("float")
    finally:
        inp.close()
    # lenslab's raw read: the same codes over 65535 as OpenImageIO gives
    codes, _ = lio.read(tmp_path / "d.png", raw=True)
    np.testing.assert_allclose(codes, theirs, atol=1e-7)  # float32 rounding of code / 65535
    # its read: linear Rec.709 light as a PQ/HLG video reads, 1.0 = 203 cd/m2 (BT.2408), by colour-science's
    # EOTF of OpenImageIO's codes and the BT.2020 -> BT.709 matrix
    ours, meta = lio.read(tmp_path / "d.png")
    v = theirs.astype(np.float64)
    light = (colour.models.eotf_ST2084(v) if transfer == 16 else
             colour.models.eotf_BT2100_HLG(v, L_B=0, L_W=1000)) / 203.0
    cs = colour.RGB_COLOURSPACES
    want = light @ colour.matrix_RGB_to_RGB(cs["ITU-R BT.2020"], cs["ITU-R BT.709"]).T
    np.testing.assert_allclose(ours, want, rtol=1e-5, atol=1e-6)  # float32 results of float64 formulas
    assert f"transfer {transfer}" in meta["attributes"]["cICP"] and "linear Rec.709" in meta["attributes"]["note"]
    assert meta["display_encoded"] is False


def test_sdr_png_has_no_cicp_chunk_and_reads_as_srgb(tmp_path):
    lio.write(tmp_path / "s.exr", scene(), pixel_type="float")
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "png", "--display", "srgb", "-o",
                 str(tmp_path / "d.png"), "-q"]) == 0
    assert "cICP" not in [k for k, _ in chunks(tmp_path / "d.png")]
    _, meta = lio.read(tmp_path / "d.png")
    assert "cICP" not in meta["attributes"]


def test_other_transfers_are_left_as_codes_and_srgb_stays_srgb(tmp_path):
    import cv2

    from lenslab.io.colour.png_cicp import with_cicp

    codes = (np.arange(24, dtype=np.uint16).reshape(2, 4, 3) * 2000)
    ok, buf = cv2.imencode(".png", codes[..., ::-1])
    for transfer, want in ((8, codes / 65535.0), (13, colour.models.eotf_sRGB(codes / 65535.0))):
        path = tmp_path / f"t{transfer}.png"
        path.write_bytes(with_cicp(buf.tobytes(), (1, transfer, 0, 1)))
        assert dict(chunks(path))["cICP"] == bytes([1, transfer, 0, 1])
        img, meta = lio.read(path)
        np.testing.assert_allclose(img, want, atol=1e-6)  # float32 of the codes, or of the sRGB EOTF
        assert ("not decoded" in meta["attributes"].get("note", "")) is (transfer == 8)
