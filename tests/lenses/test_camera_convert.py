"""``lenslab camera convert --model``: one camera model re-expressed in another, checked against values
from outside lenslab: the double sphere evaluated by its paper's formulas (transcribed here in float64),
the fitted Kannala-Brandt camera by OpenCV's ``cv2.fisheye.projectPoints`` reading the written YAML,
and COLMAP cameras by pycolmap."""

from __future__ import annotations

import re

import numpy as np
import pytest

from lenslab.cli.main import main

#: the TUM-VI double-sphere calibration (cam0 of the TUM visual-inertial dataset, 512 x 512)
FX, FY, CX, CY = 158.28600034966977, 158.2743455478755, 254.96116578191653, 256.8894394501779
XI, ALPHA = -0.17734010681185516, 0.5929141335037622
TUM_VI = (f"double-sphere:fx={FX!r},fy={FY!r},cx={CX!r},cy={CY!r},xi={XI!r},alpha={ALPHA!r},"
          "width=512,height=512")
#: the aim of the conversion, px RMS over the shared field
AIM = 0.05


def double_sphere_rays(u, v):
    """Usenko, Demmel, Cremers 2018, eqs. 40-47: OpenCV pixel -> unit ray (OpenCV frame), and validity."""
    mx, my = (u - CX) / FX, (v - CY) / FY
    r2 = mx * mx + my * my
    ok = (ALPHA <= 0.5) | (r2 <= 1.0 / (2.0 * ALPHA - 1.0))
    mz = (1.0 - ALPHA * ALPHA * r2) / (ALPHA * np.sqrt(np.abs(1.0 - (2.0 * ALPHA - 1.0) * r2)) + 1.0 - ALPHA)
    k = (mz * XI + np.sqrt(mz * mz + (1.0 - XI * XI) * r2)) / (mz * mz + r2)
    ray = np.stack([k * mx, k * my, k * mz - XI], axis=-1)
    return ray / np.linalg.norm(ray, axis=-1, keepdims=True), ok


def kannala_brandt_pixels(rays, K, D):
    """Kannala and Brandt 2006 as OpenCV states it, for any angle below 180 degrees (OpenCV pixels)."""
    theta = np.arctan2(np.hypot(rays[:, 0], rays[:, 1]), rays[:, 2])
    td = theta * (1 + D[0] * theta ** 2 + D[1] * theta ** 4 + D[2] * theta ** 6 + D[3] * theta ** 8)
    rho = np.hypot(rays[:, 0], rays[:, 1])
    s = np.where(rho > 0, td / np.where(rho > 0, rho, 1), 1.0)
    return np.column_stack([K[0, 0] * rays[:, 0] * s + K[0, 2], K[1, 1] * rays[:, 1] * s + K[1, 2]])


def test_tum_vi_double_sphere_to_kannala_brandt_meets_the_aim(tmp_path, capsys):
    cv2 = pytest.importorskip("cv2")
    out = tmp_path / "kb.yaml"
    code = main(["camera", "convert", TUM_VI, "-o", str(out), "--model", "kannala-brandt"])
    text = capsys.readouterr().out
    assert code == 0, text
    assert "aim:      RMS below 0.05 px over the shared field: met" in text
    m = re.search(r"residual: RMS (\S+) px, max (\S+) px at pixel \((\S+), (\S+)\), (\S+) deg from the axis", text)
    assert m, text
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    K, D = fs.getNode("camera_matrix").mat(), fs.getNode("distortion_coefficients").mat().ravel()
    assert int(fs.getNode("fisheye_model").real()) == 1
    fs.release()
    # every pixel centre of the source (OpenCV pixels: integers), its ray by the paper's formulas
    u, v = np.meshgrid(np.arange(512.0), np.arange(512.0))
    rays, ok = double_sphere_rays(u.ravel(), v.ravel())
    rays, want = rays[ok], np.column_stack([u.ravel(), v.ravel()])[ok]
    got = kannala_brandt_pixels(rays, K, D)
    err = np.hypot(*(got - want).T)
    rms = float(np.sqrt(np.mean(err ** 2)))
    assert rms < AIM
    assert err.max() == pytest.approx(float(m.group(2)), rel=0.2)  # the report's max, on its grid
    # OpenCV's own projection where it has one (it divides by z: the forward half-space)
    front = rays[:, 2] > 1e-3
    cvpix, _ = cv2.fisheye.projectPoints(rays[front][None].astype(np.float64), np.zeros(3), np.zeros(3), K, D)
    assert np.abs(cvpix[0] - got[front]).max() < 1e-9
    assert np.sqrt(np.mean(np.hypot(*(cvpix[0] - want[front]).T) ** 2)) < AIM


def test_the_start_follows_the_source():
    """Principal point from the source; focal length from its central scale: a double sphere maps a
    small angle t to fx t / (1 + xi) pixels (its denominator alpha d2 + (1 - alpha)(xi d1 + z) is
    1 + xi on the axis), and a Kannala-Brandt camera to fx t."""
    from lenslab.fit.params import build_space
    from lenslab.lenses import make_lens

    src = make_lens(TUM_VI, (512, 512))
    ps = build_space("kannala-brandt:width=512,height=512", (512, 512), start_from=src)
    start = dict(zip(ps.names, ps.start))
    assert start["fx"] == pytest.approx(FX / (1 + XI), rel=1e-5)  # finite differences over 0.5 px
    assert start["fy"] == pytest.approx(FY / (1 + XI), rel=1e-5)
    assert ps.fixed["cx"] == pytest.approx(CX, abs=1e-9) and ps.fixed["cy"] == pytest.approx(CY, abs=1e-9)
    # a spec for a 1024 x 1024 calibration image: the same start in its pixels (about the corner)
    ps = build_space("kannala-brandt:width=1024,height=1024", (512, 512), start_from=src)
    assert ps.fixed["cx"] == pytest.approx((CX + 0.5) * 2 - 0.5, abs=1e-9)
    assert dict(zip(ps.names, ps.start))["fx"] == pytest.approx(2 * FX / (1 + XI), rel=1e-5)


def test_a_missed_aim_says_why_with_the_residual_map_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "pinhole.txt"
    resmap = tmp_path / "residual.exr"
    code = main(["camera", "convert", TUM_VI, "-o", str(out), "--model", "opencv", "--residual-map", str(resmap)])
    cap = capsys.readouterr()
    assert code == 1
    assert "MISSED" in cap.out and "why:" in cap.out and "residual map" in cap.out
    assert "of the source's field is outside the target's" in cap.out  # a pinhole sees less than 180 deg
    assert not out.exists()
    assert "not written" in cap.err and cap.err.count("\n") == 1
    from lenslab import io

    img, _ = io.read(str(resmap))
    assert img.shape[:2] == (512, 512) and np.isnan(img).any() and np.nanmax(img) > AIM


def test_a_colmap_camera_converted_agrees_with_pycolmap(tmp_path, capsys):
    """A COLMAP EUCM camera re-expressed as OPENCV_FISHEYE in cameras.txt: both ends evaluated by pycolmap."""
    pycolmap = pytest.importorskip("pycolmap")
    w, h = 640, 480
    params = [260.0, 258.0, 320.0, 240.0, 0.63, 1.05]
    src = tmp_path / "cameras.txt"
    src.write_text(f"1 EUCM {w} {h} " + " ".join(map(repr, params)) + "\n")
    out = tmp_path / "out" / "cameras.txt"
    out.parent.mkdir()
    code = main(["camera", "convert", str(src), "-o", str(out), "--model", "kannala-brandt"])
    assert code == 0, capsys.readouterr().out
    line = [l for l in out.read_text().splitlines() if not l.startswith("#")][0].split()
    assert line[1] == "OPENCV_FISHEYE"
    a = pycolmap.Camera.create_from_model_name(1, "EUCM", 100.0, w, h)
    a.params = params
    b = pycolmap.Camera.create_from_model_name(1, "OPENCV_FISHEYE", 100.0, w, h)
    b.params = [float(p) for p in line[4:]]
    u, v = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)  # COLMAP's pixel centres
    xy = np.column_stack([u.ravel(), v.ravel()])
    rays = a.cam_ray_from_img(xy)
    front = rays[:, 2] > 1e-3  # pycolmap projects the front half-space
    got = b.img_from_cam(rays[front])
    err = np.hypot(*(got - xy[front]).T)
    assert np.sqrt(np.mean(err ** 2)) < AIM


@pytest.mark.slow
def test_fit_lens_starts_from_the_source_at_the_calibration_size(capsys):
    """``fit lens`` with the model at the source's calibration size: the principal point and focal length
    start from the source (never the 1000 x 1000 defaults' 499.5), and the fit reaches the aim; the
    fitted numbers checked by cv2.fisheye against the paper's double sphere."""
    cv2 = pytest.importorskip("cv2")
    code = main(["fit", "lens", "--from", TUM_VI, "--model", "kannala-brandt:width=512,height=512"])
    out = capsys.readouterr().out
    assert code == 0, out
    spec = re.search(r"fitted:\s+kannala-brandt:(\S+)", out).group(1)
    text = dict(item.split("=") for item in spec.split(","))
    v = {k: float(x) for k, x in text.items()}
    # the source's principal point, kept exactly: printed with the digits the fit prints (6 at least)
    for name, want in (("cx", CX), ("cy", CY)):
        digits = len(text[name].replace(".", "").lstrip("-0"))
        assert digits >= 6 and v[name] == float(f"{want:.{digits}g}"), (name, text[name])
    K = np.array([[v["fx"], 0, v["cx"]], [0, v["fy"], v["cy"]], [0, 0, 1.0]])
    D = np.array([v["k1"], v["k2"], v["k3"], v["k4"]])
    u, w = np.meshgrid(np.arange(0.0, 512.0, 4.0), np.arange(0.0, 512.0, 4.0))
    rays, ok = double_sphere_rays(u.ravel(), w.ravel())
    front = ok & (rays[:, 2] > 1e-3)
    got, _ = cv2.fisheye.projectPoints(rays[front][None], np.zeros(3), np.zeros(3), K, D)
    err = np.hypot(got[0][:, 0] - u.ravel()[front], got[0][:, 1] - w.ravel()[front])
    assert np.sqrt(np.mean(err ** 2)) < AIM


def test_an_equisolid_fisheye_becomes_kannala_brandt_with_its_taylor_series(tmp_path, capsys):
    """r = 2 f sin(theta/2) = f (theta - theta^3/24 + theta^5/1920 - theta^7/322560 + ...): converted to
    Kannala-Brandt, k1..k3 are the series' -1/24, 1/1920, -1/322560 (k4 takes up the rest of the series
    over the field, so k3 is held to 5 percent), and f is the fisheye's own."""
    out = tmp_path / "kb.toml"
    code = main(["camera", "convert", "fisheye:fov=190,mapping=equisolid", "--size", "640x480", "-o", str(out),
                 "--model", "kannala-brandt"])
    text = capsys.readouterr().out
    assert code == 0, text
    from lenslab.calibfiles import read_lens

    kb = read_lens(str(out))
    # the fisheye's focal length: r = 1 (half the width, 320 px) at theta = 95 deg
    f = 320.0 / (2 * np.sin(np.radians(95.0) / 2))
    assert kb.fx == pytest.approx(f, rel=1e-6) and kb.fy == pytest.approx(f, rel=1e-6)
    assert kb.k1 == pytest.approx(-1 / 24, rel=1e-5)
    assert kb.k2 == pytest.approx(1 / 1920, rel=1e-3)
    assert kb.k3 == pytest.approx(-1 / 322560, rel=0.05)
