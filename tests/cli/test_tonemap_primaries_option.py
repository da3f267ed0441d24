"""``lenslab tonemap --primaries``: the luminance weights of the primaries an untagged file's values are on,
refused where nothing weighs the channels, and not applied (one note) to a file whose colour lenslab converted
to Rec.709 when it read it. Expected weights: colour-science's ``RGB_COLOURSPACES[name].matrix_RGB_to_XYZ``
second row, in float64."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

colour = pytest.importorskip("colour")

RGB = np.array([0.8, 0.2, 0.1])  # one colour, far from grey (the three weights count), every output below 1
# P3-D65 chromaticities (x, y of R, G, B, white), as an EXR header holds them
P3 = (0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.3127, 0.3290)


def _luminance_back(path) -> float:
    """L from a reinhard --luminance output: out = rgb L / (1 + L) / L = rgb / (1 + L), so L = r / out_r - 1."""
    out, _ = lio.read(path)
    return float(RGB[0] / np.float64(out[0, 0, 0]) - 1.0)


def _code(argv) -> int:
    """The exit code of ``lenslab ARGV`` (returned, or argparse's SystemExit)."""
    try:
        return main(argv)
    except SystemExit as e:
        return e.code


def _pfm(tmp_path):
    path = tmp_path / "flat.pfm"
    lio.write(path, np.broadcast_to(RGB.astype(np.float32), (4, 4, 3)).copy())
    return path


@pytest.mark.parametrize("name", ["Display P3", "ITU-R BT.2020", "ACEScg"])
def test_an_untagged_file_is_weighed_by_colour_sciences_y_row(tmp_path, name):
    out = tmp_path / "out.exr"
    assert main(["tonemap", str(_pfm(tmp_path)), "-o", str(out), "--curve", "reinhard", "--luminance",
                 "--primaries", name, "-q"]) == 0
    expected = colour.RGB_COLOURSPACES[name].matrix_RGB_to_XYZ[1].astype(np.float64) @ RGB
    # the output is half floats: 2^-11 of a value, and L = r / out - 1 carries it times (1 + L) / L < 5 (L > 0.25)
    assert _luminance_back(out) == pytest.approx(expected, rel=2.0 ** -11 * 5)


def test_without_primaries_srgb_weights_apply(tmp_path):
    out = tmp_path / "out.exr"
    assert main(["tonemap", str(_pfm(tmp_path)), "-o", str(out), "--curve", "reinhard", "--luminance", "-q"]) == 0
    expected = colour.RGB_COLOURSPACES["sRGB"].matrix_RGB_to_XYZ[1] @ RGB
    assert _luminance_back(out) == pytest.approx(expected, rel=2.0 ** -11 * 5)


@pytest.mark.parametrize("extra", [[], ["--per-channel"], ["--display", "sRGB - Display"]])
def test_primaries_where_nothing_weighs_the_channels_is_a_usage_error(tmp_path, capsys, extra):
    missing = tmp_path / "not-read.pfm"  # a usage error comes before the file is read: it need not exist
    assert _code(["tonemap", str(missing), "-o", str(tmp_path / "o.png"), "--primaries", "Display P3", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--primaries" in err[0]
    assert not (tmp_path / "o.png").exists()


def test_an_unknown_colourspace_is_a_usage_error(tmp_path, capsys):
    assert _code(["tonemap", str(tmp_path / "x.pfm"), "-o", str(tmp_path / "o.png"), "--luminance",
                  "--primaries", "Display P4"]) == 2
    assert "Display P4" in capsys.readouterr().err


def test_a_file_converted_from_its_chromaticities_gets_srgb_weights_and_one_note(tmp_path, capsys):
    # an EXR on P3 primaries, tagged: read, its colour is Rec.709's (colour-science's conversion), so the
    # weights that fit the values read are sRGB's, not P3's
    p3 = colour.RGB_COLOURSPACES["Display P3"]
    rec709 = colour.RGB_COLOURSPACES["sRGB"]
    file_rgb = colour.RGB_to_RGB(RGB, rec709, p3, chromatic_adaptation_transform=None)
    path = tmp_path / "p3.exr"
    pixels = np.broadcast_to(file_rgb.astype(np.float32), (4, 4, 3)).copy()
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "chromaticities": P3},
                 {"RGB": pixels}).write(str(path))
    out = tmp_path / "out.exr"
    assert main(["tonemap", str(path), "-o", str(out), "--curve", "reinhard", "--luminance",
                 "--primaries", "Display P3"]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if "--primaries" in line]
    assert len(notes) == 1 and "not applied" in notes[0] and "chromaticities" in notes[0]
    expected = rec709.matrix_RGB_to_XYZ[1] @ RGB  # = P3's Y row on the file's values: the same light
    assert expected == pytest.approx(p3.matrix_RGB_to_XYZ[1] @ file_rgb, rel=1e-9)
    # half output (2^-11) and the float32 conversion on reading (far below)
    assert _luminance_back(out) == pytest.approx(expected, rel=2.0 ** -11 * 5)


def test_compare_tones_refuses_primaries_its_curves_do_not_weigh(tmp_path, capsys):
    assert _code(["compare-tones", str(tmp_path / "x.pfm"), "-o", str(tmp_path / "o.png"),
                  "--primaries", "Display P3"]) == 2  # clamp, reinhard, hable per channel: nothing weighs
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--primaries" in err[0]


def test_compare_tones_weighs_an_untagged_file_by_the_primaries_given(tmp_path, capsys):
    # --exposure auto on a flat image: key / L stops, L from Display P3's Y row (colour-science)
    out = tmp_path / "panels.png"
    assert main(["compare-tones", str(_pfm(tmp_path)), "-o", str(out), "--exposure", "auto",
                 "--primaries", "Display P3"]) == 0
    expected = np.log2(0.18 / (colour.RGB_COLOURSPACES["Display P3"].matrix_RGB_to_XYZ[1] @ RGB))
    said = [line for line in capsys.readouterr().err.splitlines() if "auto exposure" in line]
    assert len(said) == 1 and f"{expected:+.2f} stops" in said[0]  # printed to 0.01 stop
