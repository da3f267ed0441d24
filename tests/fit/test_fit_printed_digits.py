"""What the fits print: every fitted value with the digits the fit determines (6 significant digits, more only
where the camera needs them), as text that reads back through the spec grammar into a camera that agrees with
the one fitted within a tenth of the fit's tolerance. Checked against values from outside lenslab: the source
lens's own numbers, the Taylor series of the equisolid mapping, OpenCV's ``cv2.fisheye.projectPoints`` and a
pinhole's formula transcribed in float64."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.fit.digits import fitted_text, significant
from lenslab.lenses import Camera, make_lens, parse_spec

#: a number as the fits print it: at most 7 significant digits here (6, and 7 where noted)
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?")


def digits_of(text: str) -> int:
    mantissa = text.lstrip("+-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) if "." in text.split("e")[0] else len(mantissa.rstrip("0") or "0")


def fitted_line(out: str, label: str = "fitted") -> str:
    return re.search(rf"^{label}:\s+(\S+)", out, re.M).group(1)


def test_a_fitted_fov_is_printed_as_the_number_the_fit_found(capsys):
    """The fit recovers fov 190 to 1e-14 (max residual 8e-14 px): it prints 190, not 189.99999999999997."""
    code = main(["fit", "lens", "--from", "fisheye:fov=190,mapping=equisolid", "--model", "fisheye",
                 "--size", "256x256"])
    out = capsys.readouterr().out
    assert code == 0
    assert fitted_line(out) == "fisheye:fov=190,mapping=equisolid"
    tried = re.search(r"^tried:\s+(.*)$", out, re.M).group(1)  # the other mappings tried, in the same digits
    for spec in re.findall(r"(fisheye:\S+) -> RMS", tried):
        name, values = parse_spec(spec)
        assert name == "fisheye" and digits_of(values["fov"]) <= 6, spec


def test_a_kannala_brandt_fit_prints_the_equisolid_series_and_opencv_agrees(capsys):
    """An equisolid fisheye (r = 2 f sin(theta / 2)) fitted by Kannala-Brandt: the printed coefficients are the
    series 2 sin(theta / 2) = theta - theta^3 / 24 + theta^5 / 1920 - ..., to 6 digits, and the printed values,
    pasted into OpenCV's fisheye model, put the equisolid rays on their pixels within the fit's tolerance."""
    cv2 = pytest.importorskip("cv2")
    w = h = 512
    code = main(["fit", "lens", "--from", "fisheye:fov=150,mapping=equisolid", "--model", "kannala-brandt",
                 "--size", f"{w}x{h}"])
    out = capsys.readouterr().out
    assert code == 0
    spec = fitted_line(out)
    name, values = parse_spec(spec)  # the spec grammar reads it back
    assert name == "kannala-brandt"
    f = (w / 2) / (2 * math.sin(math.radians(150 / 4)))  # the equisolid focal length: r(75 deg) = w / 2
    assert values["fx"] == values["fy"] == significant(f) == "210.263"
    assert values["cx"] == values["cy"] == "255.5"  # OpenCV's pixel centres: the image centre is (W - 1) / 2
    assert values["k1"] == significant(-1 / 24) == "-0.0416667"
    assert values["k2"] == significant(1 / 1920) == "0.000520833"
    assert all(digits_of(v) <= 6 for v in values.values() if NUMBER.fullmatch(v)), spec
    # the printed values in OpenCV: equisolid rays, transcribed in float64, land on their pixel centres
    u, v = np.meshgrid(np.arange(0, w, 7) + 0.5, np.arange(0, h, 7) + 0.5)
    xy = np.stack([u.ravel(), v.ravel()], -1)
    r = np.hypot(xy[:, 0] - w / 2, xy[:, 1] - h / 2)
    inside = r <= w / 2  # the image circle
    xy, r = xy[inside], r[inside]
    theta = 2 * np.arcsin(r / (2 * f))
    phi = np.arctan2(xy[:, 1] - h / 2, xy[:, 0] - w / 2)
    rays = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    K = np.array([[float(values["fx"]), 0, float(values["cx"])], [0, float(values["fy"]), float(values["cy"])],
                  [0, 0, 1]])
    D = np.array([float(values[k]) for k in ("k1", "k2", "k3", "k4")])
    got, _ = cv2.fisheye.projectPoints(rays.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    err = np.hypot(*(got.reshape(-1, 2) - (xy - 0.5)).T)  # OpenCV's pixel centres are integers
    # the fit's default tolerance is 0.5 px, of which the printing may use a tenth; the fit itself is exact
    assert err.max() < 0.05, err.max()


def test_a_points_fit_prints_the_pose_and_lens_it_recovered(tmp_path, capsys):
    """Exact points of fisheye fov 185 turned by yaw 30, pitch -10: the fit recovers them to about 1e-9 and
    prints fov=185, yaw=30, pitch=-10, roll=0 (and the mappings it tried in 6 digits); the printed camera puts
    every point within a tenth of --scale."""
    truth = Camera.from_spec("fisheye:fov=185,mapping=equisolid", (400, 400), yaw=30, pitch=-10)
    rng = np.random.default_rng(7)
    xy = rng.uniform(40, 360, (40, 2))
    _, d, ok = truth.pixel_to_world(xy)
    assert ok.all()
    path = tmp_path / "points.csv"
    path.write_text("x,y,dx,dy,dz\n" + "".join(f"{a:.17g},{b:.17g},{p:.17g},{q:.17g},{r:.17g}\n"
                                               for (a, b), (p, q, r) in zip(xy, d)))
    code = main(["fit", "points", str(path), "--model", "fisheye", "--size", "400x400", "--pose", "--brief"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert fitted_line(out) == "fisheye:fov=185,mapping=equisolid"
    tried = re.findall(r"(fisheye:\S+) -> robust cost", out)  # every mapping tried, in the same digits
    assert len(tried) > 1 and all(digits_of(parse_spec(t)[1]["fov"]) <= 6 for t in tried), tried
    pose = dict(re.findall(r"(yaw|pitch|roll)=(\S+)", re.search(r"^pose:.*$", out, re.M).group(0)))
    assert {k: float(v) for k, v in pose.items()} == {"yaw": 30.0, "pitch": -10.0, "roll": 0.0}, pose
    line = re.search(r"^pose:.*$", out, re.M).group(0)  # and as the options warp and tracer render take
    assert dict(re.findall(r"--(yaw|pitch|roll) ([^ )]+)", line)) == pose, line
    pasted = Camera.from_spec(fitted_line(out), (400, 400), **{k: float(v) for k, v in pose.items()})
    back, seen = pasted.world_to_pixel(d)
    assert seen.all() and np.hypot(*(back - xy).T).max() < 0.1  # --scale 1 px: a tenth of it


def pinhole_shift(fov: float, printed: float, width: int) -> float:
    """Largest move (px) along a pinhole's width when its fov is written ``printed``: x = W/2 (1 + tan t / tan(fov/2))."""
    x = np.arange(width) + 0.5
    t = np.arctan((x - width / 2) / (width / 2) * math.tan(math.radians(fov) / 2))
    moved = width / 2 * (1 + np.tan(t) / math.tan(math.radians(printed) / 2))
    return float(np.abs(moved - x).max())


def test_more_digits_are_printed_only_where_the_camera_needs_them():
    """A 100000-pixel-wide pinhole of fov 90.00001234: 6 digits (90) move its edge by 0.011 px by the pinhole's
    formula, within a budget of 0.05 px but not of 0.005 px, where 7 digits (90.00001, 0.002 px) are printed."""
    lens = make_lens("perspective:fov=90.00001234", (100000, 100))
    assert pinhole_shift(90.00001234, 90, 100000) == pytest.approx(0.0108, abs=2e-4)
    assert pinhole_shift(90.00001234, 90.00001, 100000) < 0.005
    assert fitted_text(lens, 0.05)[0] == "perspective:fov=90"
    assert fitted_text(lens, 0.005)[0] == "perspective:fov=90.00001"
    # no budget any rounding meets: the exact value, as it reads back
    assert fitted_text(lens, 0.0)[0] == "perspective:fov=90.00001234"


def test_the_tone_fit_prints_options_tonemap_reads_back(tmp_path, capsys):
    """The printed ``tonemap:`` line, pasted after ``lenslab tonemap IN -o OUT``, gives the image the true
    parameters (exposure 0.3, white 7, which made the LDR) give, within one 16-bit code; its numbers have at most
    6 significant digits."""
    cv2 = pytest.importorskip("cv2")
    from lenslab import io, tone

    rng = np.random.default_rng(4)
    hdr = np.exp(rng.normal(-1.0, 1.5, (32, 48, 3))).astype(np.float32)
    io.write(tmp_path / "scene.exr", hdr, pixel_type="float")
    io.write(tmp_path / "look.png", tone.tonemap(hdr, "hable", 0.3, white=7.0), bits=16)
    assert main(["fit", "tone", str(tmp_path / "scene.exr"), str(tmp_path / "look.png")]) == 0
    line = re.search(r"^tonemap:\s+(.*)$", capsys.readouterr().out, re.M).group(1)
    numbers = re.findall(r"(?<=[ =])" + NUMBER.pattern + r"(?= |$)", line)
    assert len(numbers) == 2 and all(digits_of(n) <= 6 for n in numbers), line
    images = []
    for i, options in enumerate([line.split(), ["--curve", "hable", "--exposure", "0.3", "--param", "white=7"]]):
        out = tmp_path / f"{i}.png"
        assert main(["tonemap", str(tmp_path / "scene.exr"), "-o", str(out), "-q", "--bits", "16", "--no-dither",
                     *options]) == 0
        images.append(cv2.imread(str(out), cv2.IMREAD_UNCHANGED))  # the codes as written (OpenCV reads them)
    assert images[0].dtype == images[1].dtype == np.uint16
    assert np.abs(images[0].astype(np.int64) - images[1]).max() <= 1  # one 16-bit code


def test_a_camera_with_nothing_to_measure_is_printed_exactly():
    """Where no pixel centre can be checked (a budget below what the camera's own round trip keeps), no rounding
    is taken on trust: the exact values."""
    lens = make_lens("perspective:fov=60.123456789", (64, 48))
    assert fitted_text(lens, -1.0) == ("perspective:fov=60.123456789", ())
    assert fitted_text(lens, -1.0, (10.5, 0.1234567891, 0)) == ("perspective:fov=60.123456789",
                                                                ("10.5", "0.1234567891", "0"))
