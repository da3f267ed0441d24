"""Ultra HDR JPEGs written by Google's libultrahdr (imagecodecs' ``ultrahdr_encode``, libultrahdr 1.4), whose
only gain map metadata is the ISO 21496-1 block (no ``hdrgm`` XMP), read by lenslab as libultrahdr's own
decoder (``ultrahdr_decode``, float16 output: linear light) reads them.

The gain is compared, not the pixels: libultrahdr converts the base's Y'CbCr with its own matrix, and lenslab
its Display P3 ICC profile; each decoder's HDR over its own SDR (``boost=1``: the gain map's weight 0) is the
gain alone. The gain differs by colour channel (libultrahdr 1.4 writes an RGB gain map), so both are compared in
the space the gain is applied in: the base's (Display P3) where the block says so, else the alternate image's,
whose primaries the gain map image's ICC profile names and in which libultrahdr outputs
(``JpegR::applyGainMap``); colour-science converts lenslab's Rec.709 and libultrahdr's output gamut to it.

Tolerance, per pixel and channel, in stops: libultrahdr's float16 output is within 2^-11 of each value, so a
converted value ``y = M x`` is within ``2^-11 (|M| |x|)`` of the exact one; the gain's log is then within
``log2((1 + e_hdr) / (1 - e_sdr))`` with ``e`` those bounds over ``y``; libultrahdr's gain table holds 1024 entries
over GainMapMin..GainMapMax (``kGainFactorNumEntries``: one entry, (max - min) / 1023 stops); 2e-5 relative covers
its gamut matrices, printed to 6 decimals. Where the gain map is smaller than the base, the two decoders sample it
at different places (libultrahdr at ``x * w / W``, lenslab at the pixel centres): only pixels whose gain map
pixel and its 8 neighbours hold one code are compared."""

from __future__ import annotations

import io
import math

import colour
import numpy as np
import pytest
from PIL import Image

import lenslab.io as lio
from lenslab.io.gainmap.container import ISO_SIGNATURE, mpf_images

imagecodecs = pytest.importorskip("imagecodecs")
if not imagecodecs.ULTRAHDR.available:
    pytest.skip("this imagecodecs was built without libultrahdr", allow_module_level=True)
U = imagecodecs.ULTRAHDR
SPACES = {"709": "ITU-R BT.709", "P3": "Display P3", "2020": "ITU-R BT.2020"}
SDR_WHITE_NITS = 203.0  # ITU-R BT.2408's reference white, libultrahdr's kSdrWhiteNits
BLOCK, H, W = 32, 192, 256


def _scene(seed: int = 5) -> np.ndarray:
    """Flat 32 x 32 blocks of random colours from 1/4 to 32 times SDR white (several stops of highlights),
    linear Rec.709 float16 RGBA."""
    rng = np.random.default_rng(seed)
    colours = rng.uniform(0.02, 1, (H // BLOCK, W // BLOCK, 3)) * np.exp2(rng.integers(-2, 6, (H // BLOCK,
                                                                                           W // BLOCK, 1)))
    image = np.ones((H, W, 4), np.float16)
    image[..., :3] = np.kron(colours, np.ones((BLOCK, BLOCK, 1)))
    return image


def _hlg_1010102(image: np.ndarray) -> np.ndarray:
    """The same scene as packed RGBA1010102 BT.2100 HLG codes: colour-science's HLG OETF of its BT.2020 light over
    32 (the brightest block at HLG's peak)."""
    rgb = colour.RGB_to_RGB(image[..., :3].astype(np.float64), colour.RGB_COLOURSPACES[SPACES["709"]],
                            colour.RGB_COLOURSPACES[SPACES["2020"]])
    with np.errstate(invalid="ignore"):  # (colour-science evaluates both branches of the OETF)
        light = colour.models.oetf_BT2100_HLG(np.clip(rgb / 32.0, 0, 1))
    codes = np.round(np.clip(light, 0, 1) * 1023).astype(np.uint32)
    return codes[..., 0] | codes[..., 1] << 10 | codes[..., 2] << 20 | np.uint32(3) << 30


def _matrix(source: str, target: str) -> np.ndarray:
    return colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES[SPACES[source]], colour.RGB_COLOURSPACES[SPACES[target]])


def _gain_map_codes(blob: bytes) -> np.ndarray:
    at, size = mpf_images(blob)[1]
    with Image.open(io.BytesIO(blob[at:at + size])) as g:
        codes = np.asarray(g)
    return codes[..., None] if codes.ndim == 2 else codes


CASES = {  # ultrahdr_encode's settings: (input, the output gamut, the gain's space, HDRCapacityMax in stops)
    "defaults": ({}, "709", "P3", math.log2(10000 / SDR_WHITE_NITS)),
    "gamut Display P3": ({"gamut": U.CG.DISPLAY_P3}, "P3", "P3", math.log2(10000 / SDR_WHITE_NITS)),
    "gamut BT.2100": ({"gamut": U.CG.BT_2100}, "2020", "2020", math.log2(10000 / SDR_WHITE_NITS)),
    "scale 4": ({"scale": 4}, "709", "P3", math.log2(10000 / SDR_WHITE_NITS)),
    "nits 1000": ({"nits": 1000}, "709", "P3", math.log2(1000 / SDR_WHITE_NITS)),
    "nits 4000": ({"nits": 4000}, "709", "P3", math.log2(4000 / SDR_WHITE_NITS)),
    "transfer HLG": ({"transfer": U.CT.HLG, "gamut": U.CG.BT_2100}, "2020", "2020", math.log2(1000 / SDR_WHITE_NITS)),
}


def _top(case: str) -> float:
    """GainMapMax as libultrahdr 1.4 writes it: log2 of its HDR white (10000 nits for linear input, 1000 for HLG)
    over SDR white (``JpegR::generateGainMap``, one pass)."""
    return math.log2((1000 if "transfer" in CASES[case][0] else 10000) / SDR_WHITE_NITS)


def _encode(case: str) -> bytes:
    settings = CASES[case][0]
    image = _scene()
    return imagecodecs.ultrahdr_encode(_hlg_1010102(image) if "transfer" in settings else image, **settings)


@pytest.mark.parametrize("case", list(CASES))
def test_libultrahdrs_iso_only_files_read_with_its_gain(tmp_path, case):
    _, output, space, _ = CASES[case]
    blob = _encode(case)
    assert blob.count(b"hdrgm") == 0 and blob.count(ISO_SIGNATURE) == 2  # the ISO block alone speaks
    path = tmp_path / "iso.jpg"
    path.write_bytes(blob)
    hdr = imagecodecs.ultrahdr_decode(blob)[..., :3].astype(np.float64)
    sdr = imagecodecs.ultrahdr_decode(blob, boost=1.0)[..., :3].astype(np.float64)
    ours, meta = lio.read(path)
    ours_sdr, _ = lio.read(f"{path}:sdr")
    to_space, ours_to_space = _matrix(output, space), _matrix("709", space)
    theirs_hdr, theirs_sdr = hdr @ to_space.T, sdr @ to_space.T
    ours_hdr, ours_sdr = ours.astype(np.float64) @ ours_to_space.T, ours_sdr.astype(np.float64) @ ours_to_space.T
    spread = np.abs(to_space)

    def bound(x, y):  # relative error of y = M x from x's float16 rounding and the matrix's 6 decimals
        return (2.0 ** -11 + 2e-5) * np.einsum("ij,...j->...i", spread, np.abs(x)) / y

    codes = _gain_map_codes(blob)
    windows = np.lib.stride_tricks.sliding_window_view(np.pad(codes, ((1, 1), (1, 1), (0, 0)), mode="edge"), (3, 3),
                                                       axis=(0, 1))
    flat = (windows.max(axis=(3, 4)) == windows.min(axis=(3, 4))).all(axis=2)
    step = H // codes.shape[0]
    flat = flat[np.arange(H) // step][:, np.arange(W) // step]
    keep = flat & (np.minimum.reduce([a.min(axis=2) for a in (hdr, sdr, theirs_hdr, theirs_sdr, ours_sdr)]) > 0.01)
    with np.errstate(divide="ignore", invalid="ignore"):
        theirs_log, ours_log = np.log2(theirs_hdr / theirs_sdr), np.log2(ours_hdr / ours_sdr)
        tolerance = np.log2((1 + bound(hdr, theirs_hdr)) / (1 - bound(sdr, theirs_sdr))) + \
            _top(case) / 1023 + 1e-6
    diff = np.abs(theirs_log - ours_log)
    assert keep.mean() > 0.5, keep.mean()
    assert (diff <= tolerance)[keep].all(), diff[keep].max()
    assert np.ptp(ours_log[keep]) > 2.0  # gains over stops, not a flat one
    assert "metadata from its ISO 21496-1 block" in meta["attributes"]["gain_map"]
    if space == "2020":  # the alternate space, as the gain map image's ICC profile (libultrahdr's) names it
        assert "applied in the alternate image's colour space (ICC profile 'Rec2020 Gamut with " in \
            meta["attributes"]["gain_map"]


@pytest.mark.parametrize("case", list(CASES))
def test_the_metadata_is_what_libultrahdr_was_asked_to_write(tmp_path, case):
    """libultrahdr 1.4 writes GainMapMin 0, GainMapMax :func:`_top`, Gamma 1, offsets 0,
    HDRCapacityMin 0 and HDRCapacityMax log2 of ``nits`` / 203 where given (GainMapMax otherwise); the gain
    applies in the base's colour space unless the HDR gamut is BT.2100 (``JpegR::encodeJPEGR``'s use_sdr_cg).
    The block holds 32-bit rationals of float32 values: within 1e-6."""
    _, _, space, capacity = CASES[case]
    path = tmp_path / "iso.jpg"
    path.write_bytes(_encode(case))
    from lenslab.io.gainmap import prepare

    meta = prepare(path.read_bytes(), (W, H, 3)).meta
    np.testing.assert_allclose(meta.gain_map_max, [_top(case)] * 3, atol=1e-6)
    np.testing.assert_allclose(meta.gain_map_min + meta.offset_sdr + meta.offset_hdr, [0] * 9, atol=1e-6)
    np.testing.assert_allclose(meta.gamma, [1] * 3, atol=1e-6)
    assert meta.hdr_capacity_min == pytest.approx(0, abs=1e-6)
    assert meta.hdr_capacity_max == pytest.approx(capacity, abs=1e-6)
    assert meta.base_colour_space is (space == "P3") and not meta.base_is_hdr
