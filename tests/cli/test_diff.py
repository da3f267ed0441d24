"""``lenslab diff`` and :func:`lenslab.metrics.diff.diff_images` against OpenImageIO (the ``openimageio``
wheel, a test dependency): ``ImageBufAlgo.compare``'s numbers on the same pairs, ``idiff``'s exit codes
and printed figures on the same files, and the CLI's file rules."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.metrics.diff import Thresholds, diff_images, relative_error

oiio = pytest.importorskip("OpenImageIO")  # in the test extra; skipped only where the wheel is absent

#: both sum in double, but OpenImageIO takes each difference of two float32 values in float32 (a rounding
#: of up to 6e-8 relative per difference), lenslab in float64: sums agree to ~1e-9, well inside 1e-7; a
#: different definition (per-channel means, another PSNR peak) would be off by percent
RTOL = 1e-7


def pair(seed: int, shape=(24, 31, 3), scale=2.0, noise=0.2):
    rng = np.random.default_rng(seed)
    a = (rng.random(shape) * scale).astype(np.float32)
    b = (a + rng.normal(0.0, noise, shape)).astype(np.float32)
    return a, b


def oiio_compare(a, b, fail, warn, failrel=0.0, warnrel=0.0):
    return oiio.ImageBufAlgo.compare(oiio.ImageBuf(np.ascontiguousarray(a)), oiio.ImageBuf(np.ascontiguousarray(b)),
                                     fail, warn, failrel, warnrel)


PAIRS = [  # (seed, shape, scale, noise, fail, warn, fail_relative, warn_relative)
    (1, (24, 31, 3), 2.0, 0.2, 0.3, 0.1, 0.0, 0.0),
    (2, (17, 9, 3), 0.1, 0.01, 0.02, 0.005, 0.0, 0.0),  # peak below 1: PSNR's peak is the data's
    (3, (20, 20, 1), 50.0, 3.0, 5.0, 1.0, 0.0, 0.0),  # HDR grey
    (4, (16, 12, 4), 1.0, 0.05, 0.1, 0.02, 0.2, 0.3),  # relative thresholds, four channels unmasked
]


@pytest.mark.parametrize("case", PAIRS, ids=[f"seed{c[0]}" for c in PAIRS])
def test_numbers_match_openimageio_compare(case):
    seed, shape, scale, noise, fail, warn, frel, wrel = case
    a, b = pair(seed, shape, scale, noise)
    ours = diff_images(a, b, mask_alpha=False, flip="off",
                       thresholds=Thresholds(fail=fail, warn=warn, fail_relative=frel, warn_relative=wrel))
    cr = oiio_compare(a, b, fail, warn, frel, wrel)
    assert ours.mean_error == pytest.approx(cr.meanerror, rel=RTOL)
    assert ours.rms_error == pytest.approx(cr.rms_error, rel=RTOL)
    assert ours.psnr == pytest.approx(cr.PSNR, rel=RTOL)
    assert ours.max_error == pytest.approx(cr.maxerror, rel=1e-7)
    assert ours.max_at[:2] == (cr.maxx, cr.maxy) and ours.channels.index(ours.max_at[2]) == cr.maxc
    assert (ours.nwarn, ours.nfail) == (cr.nwarn, cr.nfail)


def test_alpha_mask_compares_what_openimageio_compares_on_those_pixels():
    """Masked by alpha, the figures are OpenImageIO's over the fully covered pixels' colour channels
    (given to it as a one-row image of just those pixels)."""
    a, b = pair(5, (20, 30, 4))
    a[..., 3] = 1.0
    b[..., 3] = 1.0
    a[:4, :, 3] = 0.5  # partly covered in one image
    b[:, :3, 3] = 0.0  # empty in the other
    keep = (a[..., 3] >= 0.999) & (b[..., 3] >= 0.999)
    ours = diff_images(a, b, flip="off", thresholds=Thresholds(fail=0.3, warn=0.1))
    cr = oiio_compare(a[keep][None, :, :3], b[keep][None, :, :3], 0.3, 0.1)
    assert ours.pixels == keep.sum() == 20 * 30 - 4 * 30 - 16 * 3
    assert ours.masked_out == 20 * 30 - ours.pixels
    assert ours.channels == ["R", "G", "B"]
    assert ours.mean_error == pytest.approx(cr.meanerror, rel=RTOL)
    assert ours.rms_error == pytest.approx(cr.rms_error, rel=RTOL)
    assert ours.max_error == pytest.approx(cr.maxerror, rel=1e-7)
    assert (ours.nwarn, ours.nfail) == (cr.nwarn, cr.nfail)


def test_per_channel_and_relative_errors_match_float64_formulas():
    a, b = pair(6, (10, 12, 3))
    r = diff_images(a, b, flip="off")
    a64, b64 = a.astype(np.float64), b.astype(np.float64)
    for k, c in enumerate(r.per_channel):
        d = np.abs(a64[..., k] - b64[..., k])
        rel = d / (0.5 * (np.abs(a64[..., k]) + np.abs(b64[..., k])))
        assert c.mean_abs == pytest.approx(d.mean(), rel=1e-12)
        assert c.rms_abs == pytest.approx(np.sqrt((d ** 2).mean()), rel=1e-12)
        assert c.max_abs == d.max() and c.max_at == tuple(int(i) for i in np.unravel_index(d.argmax(), d.shape)[::-1])
        assert c.max_rel == pytest.approx(rel.max(), rel=1e-12)
        assert c.mean_rel == pytest.approx(rel.mean(), rel=1e-12)
    assert relative_error(np.zeros(2), np.zeros(2)).tolist() == [0.0, 0.0]


def test_flip_is_flip_evaluators_mean():
    """Unmasked, the report's FLIP is flip-evaluator's own mean: HDR on linear values above 1, LDR on
    the sRGB encodings otherwise."""
    import flip_evaluator

    from lenslab.io.encode import encode_srgb

    a, b = pair(7, (40, 48, 3), scale=4.0, noise=0.3)
    r = diff_images(a, np.maximum(b, 0), flip="auto")
    _, mean, _ = flip_evaluator.evaluate(a, np.maximum(b, 0), "HDR", inputsRGB=False, applyMagma=False,
                                         computeMeanError=True, parameters={})
    assert r.flip_mode == "hdr" and r.flip == pytest.approx(mean, rel=1e-6)
    a, b = np.clip(a / 4, 0, 1), np.clip(b / 4, 0, 1)
    r = diff_images(a, b, flip="auto")
    _, mean, _ = flip_evaluator.evaluate(encode_srgb(a), encode_srgb(b), "LDR", inputsRGB=True, applyMagma=False,
                                         computeMeanError=True, parameters={})
    assert r.flip_mode == "ldr" and r.flip == pytest.approx(mean, rel=1e-6)


def idiff() -> str:
    path = Path(oiio.__file__).parent / "bin" / "idiff"
    if not path.exists():
        import shutil

        path = shutil.which("idiff")
    assert path, "the openimageio wheel installs idiff"
    return str(path)


def idiff_figures(text: str) -> dict:
    out = {}
    for key, pat in (("mean", r"Mean error = (\S+)"), ("rms", r"RMS error = (\S+)"), ("psnr", r"Peak SNR = (\S+)"),
                     ("max", r"Max error\s+= (\S+)")):
        m = re.search(pat, text)
        if m:
            out[key] = float(m.group(1))
    return out


@pytest.mark.parametrize("opts", [
    ["--fail", "0.3", "--warn", "0.1"],  # FAILURE
    ["--fail", "2", "--warn", "0.1"],  # WARNING
    ["--fail", "2", "--warn", "2"],  # PASS
    ["--fail", "0.3", "--warn", "0.1", "--fail-percent", "50", "--warn-percent", "1"],  # WARNING by share
    ["--fail", "0.3", "--warn", "0.1", "--fail-percent", "50", "--warn-percent", "90"],  # PASS by share
    ["--fail", "2", "--warn", "2", "--hard-fail", "0.4"],  # FAILURE by one pixel
    ["--fail", "0.05", "--warn", "0.05", "--fail-relative", "0.5", "--warn-relative", "0.2"],
    ["--fail", "0.3", "--warn", "0.1", "--allow-failures", "1000"],
])
def test_exit_codes_and_figures_match_idiff(tmp_path, opts, capsys):
    a, b = pair(8, (24, 32, 3))
    fa, fb = tmp_path / "a.exr", tmp_path / "b.exr"
    write(fa, a, pixel_type="float")
    write(fb, b, pixel_type="float")
    idiff_opts = [o.replace("--", "-").replace("-fail-percent", "-failpercent").replace("-warn-percent", "-warnpercent")
                  .replace("-hard-fail", "-hardfail").replace("-fail-relative", "-failrelative")
                  .replace("-warn-relative", "-warnrelative").replace("-allow-failures", "-allowfailures")
                  for o in opts]
    theirs = subprocess.run([idiff(), "-v", *idiff_opts, str(fa), str(fb)], capture_output=True, text=True)
    code = main(["diff", str(fa), str(fb), "--json", "--flip", "off", *opts])
    report = json.loads(capsys.readouterr().out)
    assert code == theirs.returncode == report["exit_code"]
    fig = idiff_figures(theirs.stdout)
    assert report["mean_error"] == pytest.approx(fig["mean"], rel=1e-5)  # idiff prints 6 digits
    assert report["rms_error"] == pytest.approx(fig["rms"], rel=1e-5)
    assert report["psnr"] == pytest.approx(fig["psnr"], rel=1e-5)
    assert report["max_error"] == pytest.approx(fig["max"], rel=1e-5)


def test_cli_file_rules(tmp_path, capsys):
    a, b = pair(9, (8, 10, 3))
    fa, fb, out = tmp_path / "a.exr", tmp_path / "b.exr", tmp_path / "err.exr"
    write(fa, a, pixel_type="float")
    write(fb, b, pixel_type="float")
    assert main(["diff", str(fa), str(fb), "-o", str(out), "-q", "--flip", "off"]) == 2  # FAILURE at 1e-6
    assert capsys.readouterr().out.strip() == "FAILURE"
    emap = read(out)[0]
    np.testing.assert_allclose(emap[..., :3], np.abs(a - b), rtol=1e-6)
    assert np.all(emap[..., 3] == 1.0)
    before = out.read_bytes()
    assert main(["diff", str(fa), str(fb), "-o", str(out), "-q", "--flip", "off"]) == 4  # exists: never replaced
    assert out.read_bytes() == before and "already exists" in capsys.readouterr().err
    assert main(["diff", str(fa), str(fb), "-o", str(fa), "--overwrite", "-q"]) == 2  # an input: a usage error
    assert read(fa)[0].shape == a.shape and "input" in capsys.readouterr().err
    assert main(["diff", str(fa), str(tmp_path / "missing.exr")]) == 4
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.exr" in err[0]
    write(tmp_path / "small.exr", a[:4], pixel_type="float")
    assert main(["diff", str(fa), str(tmp_path / "small.exr")]) == 3
    assert "differ in size" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["diff", str(fa), str(fb), "--warn-percent", "120"])
    assert exc.value.code == 2
    assert main(["diff", str(fa), str(fa), "-q"]) == 0
    (tmp_path / "other").mkdir()
    write(tmp_path / "other" / "a.exr", a, pixel_type="float")
    assert main(["diff", str(fa), str(tmp_path / "other"), "-q"]) == 0  # a folder: the file of A's name in it
    assert not any(p.name.startswith(".") or p.suffix == ".tmp" for p in tmp_path.iterdir())  # no leftovers
    assert os.listdir(tmp_path)


def test_nonfinite_values_fail_and_are_counted():
    a, b = pair(10, (6, 6, 3))
    b[2, 3, 1] = np.nan
    a[0, 0, 0] = b[0, 0, 0] = np.inf  # the same infinity in both: no difference
    r = diff_images(a, b, flip="off", thresholds=Thresholds(fail=10, warn=10))
    assert r.nonfinite == 1 and r.nfail == 1 and r.max_error == math.inf and r.verdict == 2
    assert r.pixels == 36 and math.isfinite(r.mean_error)


images = arrays(np.float32, st.tuples(st.integers(2, 9), st.integers(2, 9), st.sampled_from([1, 3])),
                elements=st.floats(-100, 100, width=32))


@settings(max_examples=40, deadline=None)
@given(images, st.floats(0.125, 8.0))
def test_properties(a, s):
    """Identity passes with no error; the measure is symmetric; scaling both images by s scales the
    absolute errors by s and leaves relative errors (and PSNR, where the peak stays above 1) alone."""
    same = diff_images(a, a.copy(), flip="off")
    assert same.verdict == 0 and same.max_error == 0 and same.psnr == math.inf and same.nfail == 0
    b = (a[::-1] * np.float32(0.5) + np.float32(1.0)).astype(np.float32)
    ab, ba = diff_images(a, b, flip="off"), diff_images(b, a, flip="off")
    assert ab.mean_error == pytest.approx(ba.mean_error) and ab.max_error == ba.max_error
    sa, sb = (a * np.float32(s)).astype(np.float32), (b * np.float32(s)).astype(np.float32)
    scaled = diff_images(sa, sb, flip="off")
    if ab.rms_error > 1e-3:
        assert scaled.mean_error == pytest.approx(ab.mean_error * s, rel=1e-5)
        assert scaled.rms_error == pytest.approx(ab.rms_error * s, rel=1e-5)
        peak = max(np.abs(a).max(), np.abs(b).max())
        if min(peak, peak * s) >= 1:  # PSNR's peak is never below 1 (OpenImageIO's rule)
            assert scaled.psnr == pytest.approx(ab.psnr, abs=1e-4)
        for x, y in zip(scaled.per_channel, ab.per_channel):
            assert x.max_rel == pytest.approx(y.max_rel, rel=1e-4, abs=1e-6)


def test_per_channel_figures_match_openimageio_pixel_stats():
    """Per channel, mean, RMS and max absolute error are ``computePixelStats`` of OpenImageIO's
    ``absdiff`` image (``avg``, ``sqrt(sum2 / count)``, ``max``), and the relative error's mean and max
    those of ``absdiff / ((abs(A) + abs(B)) / 2)`` computed by OpenImageIO's own image arithmetic (float32
    there: 1e-6 relative)."""
    a, b = pair(11, (18, 22, 3), scale=3.0, noise=0.3)
    a[0, 0] = b[0, 0] = 0.0  # both zero: relative error 0, as in the report
    r = diff_images(a, b, mask_alpha=False, flip="off")
    A, B = oiio.ImageBuf(a), oiio.ImageBuf(b)
    ad = oiio.ImageBufAlgo.absdiff(A, B)
    st = oiio.ImageBufAlgo.computePixelStats(ad)
    n = a.shape[0] * a.shape[1]
    mean_ab = oiio.ImageBufAlgo.mul(oiio.ImageBufAlgo.add(oiio.ImageBufAlgo.abs(A), oiio.ImageBufAlgo.abs(B)), 0.5)
    rel = oiio.ImageBufAlgo.div(ad, mean_ab)  # OpenImageIO's div gives 0 where the divisor is 0
    rst = oiio.ImageBufAlgo.computePixelStats(rel)
    for k, c in enumerate(r.per_channel):
        assert c.mean_abs == pytest.approx(st.avg[k], rel=1e-6)
        assert c.rms_abs == pytest.approx(math.sqrt(st.sum2[k] / n), rel=1e-6)
        assert c.max_abs == pytest.approx(st.max[k], rel=1e-7)
        assert c.mean_rel == pytest.approx(rst.avg[k], rel=1e-6)
        assert c.max_rel == pytest.approx(rst.max[k], rel=1e-6)


def test_chunks_do_not_change_the_figures(monkeypatch):
    """The image is measured in chunks of pixels; chunk edges change no figure (a tie for the max keeps
    its first pixel, masked and non-finite pixels are counted once)."""
    import lenslab.metrics.diff as diffmod

    a, b = pair(12, (13, 17, 4))
    a[..., 3], b[..., 3] = 1.0, 1.0
    a[2:4, :, 3] = 0.0
    b[5, 6, 1] = np.inf
    b[7, 3, 0] = a[7, 3, 0] + 5.0  # the largest error, tied with another pixel in a later chunk
    b[11, 15, 0] = a[11, 15, 0] + 5.0
    whole = diff_images(a, b, flip="off", thresholds=Thresholds(fail=0.3, warn=0.1)).to_dict()
    monkeypatch.setattr(diffmod, "CHUNK", 7)
    chunked = diff_images(a, b, flip="off", thresholds=Thresholds(fail=0.3, warn=0.1)).to_dict()
    assert whole["per_channel"][0]["max_at"] == [3, 7]
    for key in ("pixels", "masked_out", "nonfinite", "nwarn", "nfail", "max_at", "max_error", "verdict"):
        assert chunked[key] == whole[key], key
    for key in ("mean_error", "rms_error", "psnr"):
        assert chunked[key] == pytest.approx(whole[key], rel=1e-12), key
    for x, y in zip(chunked["per_channel"], whole["per_channel"]):
        assert x["max_at"] == y["max_at"] and x["max_rel"] == y["max_rel"]
        assert x["mean_abs"] == pytest.approx(y["mean_abs"], rel=1e-12)


def test_files_of_different_cameras_get_a_note(tmp_path, capsys):
    # a traced view and a warp from a panorama recorded elsewhere show different views: diff says so
    from lenslab.lenses import Camera

    image = np.full((8, 8, 3), 0.5, np.float32)
    here = Camera.from_spec("fisheye:fov=180", (8, 8), eye=(0.278, 0.273, 0.001))
    there = Camera.from_spec("fisheye:fov=180", (8, 8), eye=(0.278, 0.3, 0.06))
    write(tmp_path / "a.exr", image, camera=here)
    write(tmp_path / "b.exr", image, camera=there)
    write(tmp_path / "c.exr", image, camera=here)
    assert main(["diff", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "--flip", "off"]) == 0
    err = capsys.readouterr().err
    assert "record different cameras (eye points (0.278, 0.273, 0.001) and (0.278, 0.3, 0.06))" in err
    assert main(["diff", str(tmp_path / "a.exr"), str(tmp_path / "c.exr"), "--flip", "off"]) == 0
    assert "different cameras" not in capsys.readouterr().err
