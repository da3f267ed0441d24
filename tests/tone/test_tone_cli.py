"""The tonemap, curves and compare-tones commands, and the tone benchmark, end to end on small files."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import io, tone
from lenslab.cli.main import main


@pytest.fixture()
def hdr(tmp_path):
    rng = np.random.default_rng(0)
    img = (0.18 * np.exp2(rng.normal(0, 2, (24, 40, 3)))).astype(np.float32)
    img[2, 3, 0] = np.nan
    img[4, 5, 1] = np.inf
    img[6, 7, 2] = -2.0
    path = tmp_path / "in.pfm"
    io.write(path, img)
    return path, img


def test_tonemap_command_writes_what_the_api_computes_and_reports_repairs(hdr, tmp_path, capsys):
    path, img = hdr
    out = tmp_path / "out.png"
    assert main(["tonemap", str(path), "-o", str(out), "--curve", "aces", "--exposure", "1",
                 "--luminance", "--no-dither", "--bits", "16"]) == 0
    err = capsys.readouterr().err
    assert "1 NaN set to 0" in err and "1 +inf set to white" in err and "1 negative value, down to -2, set to 0" in err  # the -2.0 put in above
    got, meta = io.read(out)
    with pytest.warns(tone.ToneWarning, match="1 NaN"):
        ref = tone.tonemap(io.read(path)[0], "aces", exposure=1, mode="luminance")
    # 16-bit sRGB codes: one code step is at most 1/65535 * slope of the EOTF (< 12.92) in linear light
    np.testing.assert_allclose(got, ref, atol=12.92 / 65535)


def test_tonemap_command_params_and_auto_exposure(hdr, tmp_path, capsys):
    path, _ = hdr
    out = tmp_path / "out.pfm"
    assert main(["tonemap", str(path), "-o", str(out), "--param", "preset=gdc", "--param", "white=8",
                 "--exposure", "auto"]) == 0
    assert "auto exposure" in capsys.readouterr().err
    got, _ = io.read(out)
    src = io.read(path)[0]
    ev = tone.auto_exposure(src)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tone.ToneWarning)
        ref = tone.tonemap(src, "hable", exposure=ev, preset="gdc", white=8)
    np.testing.assert_array_equal(got, ref)  # PFM keeps the float32 values exactly


def test_tonemap_command_errors_are_clear(hdr, tmp_path, capsys):
    path, _ = hdr
    # a bad curve or parameter is a usage error: exit code 2, one line
    assert main(["tonemap", str(path), "-o", str(tmp_path / "x.png"), "--curve", "nope"]) == 2
    err = capsys.readouterr().err
    assert "unknown tone curve 'nope'" in err and "pbr-neutral" in err
    assert main(["tonemap", str(path), "-o", str(tmp_path / "x.png"), "--param", "white"]) == 2
    assert "NAME=VALUE" in capsys.readouterr().err
    assert main(["tonemap", str(path), "-o", str(tmp_path / "x.png"), "--param", "white=0"]) == 2
    assert "out of range" in capsys.readouterr().err


def test_curves_command_plots_and_lists(tmp_path, capsys):
    out = tmp_path / "curves.png"
    assert main(["curves", "-o", str(out)]) == 0
    chart, _ = io.read(out)
    assert chart.shape[0] > 300 and chart.shape[1] > 600
    assert main(["curves", "--list"]) == 0
    listing = capsys.readouterr().out
    for name in tone.CURVES:
        assert name in listing
    assert "exposure_bias=2" in listing


def test_compare_tones_strip_has_one_labelled_panel_per_curve(hdr, tmp_path, capsys):
    path, img = hdr
    out = tmp_path / "strip.png"
    assert main(["compare-tones", str(path), "-o", str(out), "--curves", "clamp,reinhard,hable", "--no-dither"]) == 0
    strip, _ = io.read(out)
    h, w = img.shape[:2]
    assert strip.shape[:2] == (h, 3 * w + 2 * 4)  # three panels and two 4-pixel gaps
    err = capsys.readouterr().err
    assert err.count("NaN set to 0") == 1  # the input's repairs are reported once
    # away from the label, the middle panel is the reinhard image (8-bit codes: half a code step,
    # < 0.5/255 * 12.92 in linear light at worst)
    panel = strip[16:, w + 4: 2 * w + 4]
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tone.ToneWarning)
        ref = tone.tonemap(io.read(path)[0], "reinhard")[16:]
    np.testing.assert_allclose(panel, ref, atol=0.5 / 255 * 12.92)


def test_bench_tone_quick_prints_ratios(capsys):
    assert main(["bench", "tone", "--quick", "--curves", "clamp,hable", "--repeat", "1", "--no-local"]) == 0
    out = capsys.readouterr().out
    assert "numpy.clip (baseline)" in out and "hable [luminance]" in out and "x baseline" in out
