"""Calibration files: written by cv2.FileStorage and by hand in Kalibr, COLMAP and OCamCalib formats,
read back to the same camera; lenslab's OpenCV YAML read by cv2.FileStorage; one-line errors for bad files;
the ``lenslab camera`` command."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from lenslab.calibfiles import CameraFileError, read_lens, write_lens
from lenslab.cli.main import main
from lenslab.errors import LensError
from lenslab.lenses import Camera, make_lens

#: a value that goes through a text file and back, or through COLMAP's +0.5, keeps ~1e-13 px
PX = 1e-9


def assert_same(a, b):
    """Same model, size and parameters (numbers to PX)."""
    assert a.name == b.name and (a.width, a.height) == (b.width, b.height)
    va, vb = a.param_values(), b.param_values()
    assert va.keys() == vb.keys()
    for k in va:
        if isinstance(va[k], float):
            assert va[k] == pytest.approx(vb[k], abs=PX), k
        else:
            assert va[k] == vb[k], k


def fs_write(path, **entries):
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    for k, v in entries.items():
        fs.write(k, v)
    fs.release()


K = np.array([[900.0, 0.0, 641.3], [0.0, 880.0, 478.9], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("suffix", [".yaml", ".json", ".xml"])
@pytest.mark.parametrize("coeffs,extra,spec", [
    ([-0.28, 0.09, 0.001, -0.0015, 0.01], {}, "opencv:k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=0.01"),
    ([-0.28, 0.09, 0.001, -0.0015, 0.01, 0.02, 0.001, 0.0005], {},
     "opencv:k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=0.01,k4=0.02,k5=0.001,k6=0.0005"),
    ([-0.28, 0.09, 0.001, -0.0015, 0.01, 0.02, 0.001, 0.0005, 1e-3, 2e-4, 3e-4, 4e-4, 0.0, 0.0], {},
     "opencv:k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=0.01,k4=0.02,k5=0.001,k6=0.0005,s1=1e-3,s2=2e-4,s3=3e-4,s4=4e-4"),
    ([0.05, -0.01, 0.003, -0.0005], {"fisheye_model": 1}, "kannala-brandt:k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005"),
    ([0.05, -0.01, 0.003, -0.0005], {"distortion_model": "equidistant"},
     "kannala-brandt:k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005"),
    ([-0.05, 0.01, 0.001, -0.002], {"xi": 1.6}, "omnidir:xi=1.6,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002"),
])
def test_files_written_by_cv2_filestorage(tmp_path, suffix, coeffs, extra, spec):
    path = tmp_path / ("cal" + suffix)
    fs_write(path, image_width=1280, image_height=960, camera_matrix=K,
             distortion_coefficients=np.array(coeffs).reshape(-1, 1), **extra)
    got = read_lens(str(path))
    want = make_lens(spec + ",fx=900,fy=880,cx=641.3,cy=478.9,width=1280,height=960", (1280, 960))
    assert_same(got, want)
    # and written back: cv2.FileStorage reads lenslab's file to the same matrices
    out = tmp_path / ("back" + suffix)
    write_lens(out, got)
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    np.testing.assert_array_equal(fs.getNode("camera_matrix").mat(), K)
    d = fs.getNode("distortion_coefficients").mat().ravel()
    np.testing.assert_array_equal(d, np.array(coeffs)[:d.size])
    assert fs.getNode("image_width").real() == 1280 and fs.getNode("image_height").real() == 960
    fs.release()
    assert_same(read_lens(str(out)), want)


KALIBR = """\
cam0:
  camera_model: pinhole
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  distortion_model: radtan
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, 0.1]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  intrinsics: [190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504]
  distortion_model: equidistant
  distortion_coeffs: [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182]
  resolution: [512, 512]
cam2:
  camera_model: omni
  intrinsics: [1.6, 700.0, 701.0, 640.0, 480.0]
  distortion_model: radtan
  distortion_coeffs: [-0.05, 0.01, 0.001, -0.002]
  resolution: [1280, 960]
cam3:
  camera_model: ds
  intrinsics: [-0.171, 0.572, 158.286, 158.274, 254.962, 256.895]
  distortion_model: none
  distortion_coeffs: []
  resolution: [512, 512]
cam4:
  camera_model: eucm
  intrinsics: [0.626, 1.04, 157.98, 157.93, 254.98, 256.89]
  distortion_model: none
  distortion_coeffs: []
  resolution: [512, 512]
"""
KALIBR_WANT = {
    "cam0": "opencv:fx=458.654,fy=457.296,cx=367.215,cy=248.375,k1=-0.28340811,k2=0.07395907,p1=0.00019359,"
            "p2=1.76187114e-05,width=752,height=480",
    "cam1": "kannala-brandt:fx=190.97847715128717,fy=190.9733070521226,cx=254.93170605935475,cy=256.8974428996504,"
            "k1=0.0034823894022493434,k2=0.0007150348452162257,k3=-0.0020532361418706202,"
            "k4=0.00020293673591811182,width=512,height=512",
    "cam2": "omnidir:xi=1.6,fx=700,fy=701,cx=640,cy=480,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,width=1280,height=960",
    "cam3": "double-sphere:xi=-0.171,alpha=0.572,fx=158.286,fy=158.274,cx=254.962,cy=256.895,width=512,height=512",
    "cam4": "eucm:alpha=0.626,beta=1.04,fx=157.98,fy=157.93,cx=254.98,cy=256.89,width=512,height=512",
}


@pytest.mark.parametrize("cam", sorted(KALIBR_WANT))
def test_kalibr_camchain_by_hand(tmp_path, cam):
    path = tmp_path / "camchain.yaml"
    path.write_text(KALIBR)
    spec = KALIBR_WANT[cam]
    w, h = (int(spec.split("width=")[1].split(",")[0]), int(spec.split("height=")[1]))
    got = read_lens(f"{path}#{cam}")
    assert_same(got, make_lens(spec, (w, h)))
    out = tmp_path / "one.yaml"
    write_lens(out, got, "kalibr")
    assert_same(read_lens(str(out)), got)


def test_kalibr_needs_a_pick_when_it_holds_several(tmp_path):
    path = tmp_path / "camchain.yaml"
    path.write_text(KALIBR)
    with pytest.raises(CameraFileError, match=r"holds 5 cameras; pick one as .*#ID \(IDs: cam0, cam1"):
        read_lens(str(path))


COLMAP = """\
# Camera list with one line of data per camera:
#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]
# Number of cameras: 10
1 SIMPLE_PINHOLE 3072 2304 2559.81 1536 1152
2 PINHOLE 3072 2304 2560.56 2560.56 1536 1152
3 SIMPLE_RADIAL 3072 2304 2559.69 1536 1152 -0.0218531
4 RADIAL 3072 2304 2559.69 1536 1152 -0.0218531 0.001
5 OPENCV 3072 2304 2559.69 2560.1 1536.5 1152.2 -0.02 0.001 0.0001 -0.0002
6 FULL_OPENCV 3072 2304 2559.69 2560.1 1536.5 1152.2 -0.02 0.001 0.0001 -0.0002 0.003 0.01 0.002 0.0001
7 OPENCV_FISHEYE 1280 1024 400 401 640.7 512.2 0.05 -0.01 0.003 -0.0005
8 THIN_PRISM_FISHEYE 1280 1024 400 401 640.7 512.2 0.05 -0.01 0.001 -0.002 0.003 -0.0005 0.0004 -0.0003
9 RADIAL_FISHEYE 1280 1024 400 640.7 512.2 0.05 -0.01
10 FOV 1280 1024 600 601 640.7 512.2 0.9
"""
#: COLMAP's principal point is OpenCV's + 0.5 (COLMAP's models.h: the top-left pixel centre is (0.5, 0.5))
COLMAP_WANT = {
    "1": "opencv:fx=2559.81,fy=2559.81,cx=1535.5,cy=1151.5,width=3072,height=2304",
    "2": "opencv:fx=2560.56,fy=2560.56,cx=1535.5,cy=1151.5,width=3072,height=2304",
    "3": "opencv:fx=2559.69,fy=2559.69,cx=1535.5,cy=1151.5,k1=-0.0218531,width=3072,height=2304",
    "4": "opencv:fx=2559.69,fy=2559.69,cx=1535.5,cy=1151.5,k1=-0.0218531,k2=0.001,width=3072,height=2304",
    "5": "opencv:fx=2559.69,fy=2560.1,cx=1536,cy=1151.7,k1=-0.02,k2=0.001,p1=0.0001,p2=-0.0002,width=3072,height=2304",
    "6": "opencv:fx=2559.69,fy=2560.1,cx=1536,cy=1151.7,k1=-0.02,k2=0.001,p1=0.0001,p2=-0.0002,k3=0.003,k4=0.01,"
         "k5=0.002,k6=0.0001,width=3072,height=2304",
    "7": "kannala-brandt:fx=400,fy=401,cx=640.2,cy=511.7,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,width=1280,height=1024",
    "8": "kannala-brandt:fx=400,fy=401,cx=640.2,cy=511.7,k1=0.05,k2=-0.01,p1=0.001,p2=-0.002,k3=0.003,k4=-0.0005,"
         "s1=0.0004,s3=-0.0003,width=1280,height=1024",
    "9": "kannala-brandt:fx=400,fy=400,cx=640.2,cy=511.7,k1=0.05,k2=-0.01,width=1280,height=1024",
    "10": "devernay-fov:fx=600,fy=601,cx=640.2,cy=511.7,omega=0.9,width=1280,height=1024",
}


@pytest.mark.parametrize("cid", sorted(COLMAP_WANT))
def test_colmap_cameras_txt_by_hand(tmp_path, cid):
    path = tmp_path / "cameras.txt"
    path.write_text(COLMAP)
    got = read_lens(f"{path}#{cid}")
    want = COLMAP_WANT[cid]
    assert_same(got, make_lens(want, (int(want.split("width=")[1].split(",")[0]), int(want.split("height=")[1]))))
    out = tmp_path / "out.txt"
    write_lens(out, got)
    assert_same(read_lens(str(out)), got)


def test_colmap_principal_point_at_the_image_centre_looks_down_the_axis(tmp_path):
    """COLMAP's (W/2, H/2) is the image centre (its pixel centres sit at +0.5), so is lenslab's."""
    path = tmp_path / "cameras.txt"
    path.write_text("1 SIMPLE_PINHOLE 640 480 500 320 240\n")
    lens = read_lens(str(path))
    d, ok = lens.pixel_to_dir([[320.0, 240.0]])
    assert ok[0] and np.array_equal(d[0], [0.0, 0.0, 1.0])


OCAM_TXT = """\
#polynomial coefficients for the DIRECT mapping function (ocam_model.ss in MATLAB). These are used by cam2world

5 -2.895569e+02 0.000000e+00 1.538894e-03 -3.140320e-06 7.206996e-09 

#polynomial coefficients for the inverse mapping function (ocam_model.invpol in MATLAB). These are used by world2cam

13 434.372025 226.016722 -31.205890 43.418508 11.945692 -5.582063 36.541804 -10.674868 -55.334360 1.105775 43.550131 25.374995 4.505945 

#center: "row" and "column", starting from 0 (C convention)

390.949324 423.714757

#affine parameters "c", "d", "e"

0.999134 -0.000325 -0.000071

#image size: "height" and "width"

800 848
"""


def test_ocamcalib_calib_results_by_hand(tmp_path):
    path = tmp_path / "calib_results.txt"
    path.write_text(OCAM_TXT)
    got = read_lens(str(path))
    assert got.name == "ocam" and (got.width, got.height) == (848, 800)
    assert (got.xc, got.yc, got.c, got.d, got.e) == (390.949324, 423.714757, 0.999134, -0.000325, -0.000071)
    np.testing.assert_array_equal(got.pol_c, [-2.895569e02, 0.0, 1.538894e-03, -3.140320e-06, 7.206996e-09])
    assert got.invpol_c.size == 13
    out = tmp_path / "calib_results_out.txt"
    write_lens(out, got)
    assert_same(read_lens(str(out)), got)


BAD = [
    ("cal.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n",
     "missing key 'camera_matrix'"),
    ("cal.yaml", "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
     "   data: [500., 0., 320., 0., 500., 240., 0., 0., 1.]\ndistortion_coefficients: !!opencv-matrix\n"
     "   rows: 1\n   cols: 4\n   dt: d\n   data: [0., 0., 0., 0.]\n", "missing key 'image_width'"),
    ("cal.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n"
     "   rows: 3\n   cols: 3\n   dt: d\n   data: [500., 0., 320., 0., 500., 240., 0., 0., 1.]\n"
     "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   data: [0., 0., 0.]\n",
     "'distortion_coefficients' needs 4, 5, 8, 12 or 14 numbers, got 3"),
    ("cal.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ndistortion_model: kb8\n"
     "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
     "   data: [500., 0., 320., 0., 500., 240., 0., 0., 1.]\ndistortion_coefficients: !!opencv-matrix\n"
     "   rows: 1\n   cols: 4\n   dt: d\n   data: [0., 0., 0., 0.]\n", "unknown distortion_model 'kb8'"),
    ("camchain.yaml", KALIBR.replace("camera_model: ds", "camera_model: dss"), "cam3: unknown camera_model 'dss'"),
    ("camchain.yaml", KALIBR.replace("  intrinsics: [458.654, 457.296, 367.215, 248.375]\n", ""),
     "cam0: missing key 'intrinsics'"),
    ("camchain.yaml", KALIBR.replace("distortion_model: radtan", "distortion_model: fov", 1),
     "cam0: unknown distortion_model 'fov'"),
    ("camchain.yaml", KALIBR.replace("[-0.05, 0.01, 0.001, -0.002]", "[-0.05, 0.01]"),
     "cam2: key 'distortion_coeffs' needs 4 numbers, got 2"),
    ("cameras.txt", "1 SIMPLE_PINHOLE 640 480 500 320\n", "line 1: SIMPLE_PINHOLE takes 3 parameters"),
    ("cameras.txt", "# c\n1 FISHEYE_624 640 480 500 320 240\n", "line 2: unknown camera model 'FISHEYE_624'"),
    ("cameras.txt", "1 PINHOLE 640 x 500 500 320 240\n", "line 1: WIDTH, HEIGHT and the parameters must be numbers"),
    ("calib_results.txt", OCAM_TXT.rsplit("#image size", 1)[0], "missing the size line (height width)"),
    ("calib_results.txt", OCAM_TXT.replace("5 -2.895569e+02", "4 -2.895569e+02"),
     "the polynomial line must start with its count of coefficients"),
    ("notes.txt", "hello\n", "not a calibration file lenslab knows"),
]


@pytest.mark.parametrize("name,text,message", BAD, ids=[b[2][:40] for b in BAD])
def test_bad_files_get_one_line_errors(tmp_path, name, text, message, capsys):
    path = tmp_path / name
    path.write_text(text)
    spec = str(path) + ("#cam0" if "cam0" in message else "#cam2" if "cam2" in message else
                        "#cam3" if "cam3" in message else "")
    with pytest.raises(CameraFileError) as info:
        read_lens(spec)
    text = str(info.value)
    assert message in text and "\n" not in text and text.startswith(str(path))
    # the command says the same on one line, exit status 1 (a failed input)
    assert main(["camera", "show", spec]) == 1
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_camera_command_converts_kalibr_to_a_yaml_cv2_reads(tmp_path, capsys):
    src = tmp_path / "camchain.yaml"
    src.write_text(KALIBR)
    out = tmp_path / "fisheye.yaml"
    assert main(["camera", "convert", f"{src}#cam1", "-o", str(out)]) == 0
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    assert fs.getNode("fisheye_model").real() == 1
    np.testing.assert_array_equal(fs.getNode("camera_matrix").mat(),
                                  [[190.97847715128717, 0, 254.93170605935475], [0, 190.9733070521226, 256.8974428996504],
                                   [0, 0, 1]])
    fs.release()
    # never overwrites without --overwrite, never the input, one-line errors
    assert main(["camera", "convert", f"{src}#cam1", "-o", str(out)]) == 1  # exists: known from the disk
    capsys.readouterr()
    # the input named as the output: a usage error, known from the names (exit 2), as in every command
    assert main(["camera", "convert", str(out), "-o", str(out), "--overwrite"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        f"lenslab camera convert: error: {out}: is an input of this command; it is never written over, even with "
        "--overwrite: choose another output name"]
    # COLMAP has no double-sphere: a bad choice of output, a usage error (2)
    assert main(["camera", "convert", f"{src}#cam3", "-o", str(tmp_path / "ds.txt")]) == 2
    assert "COLMAP has no double-sphere model" in capsys.readouterr().err
    assert not (tmp_path / "ds.txt").exists()
    assert main(["camera", "show", str(out)]) == 0
    shown = capsys.readouterr().out
    first = shown.splitlines()[0]  # FILE: MODEL (what it is), WxH
    assert first.startswith(f"{out}: kannala-brandt (") and first.endswith("), 512x512") and "spec: kannala-brandt:" in shown
    with pytest.raises(SystemExit) as exit_info:
        main(["camera", "convert", str(src)])
    assert exit_info.value.code == 2


def test_a_camera_file_works_wherever_a_lens_spec_does(tmp_path):
    path = tmp_path / "cameras.txt"
    path.write_text(COLMAP)
    lens = make_lens(f"{path}#7", (2560, 2048))  # another size: scaled about the corner
    assert lens.fx == 800 and lens.cx + 0.5 == (640.2 + 0.5) * 2
    cam = Camera.from_spec(f"{path}#7", (1280, 1024), yaw=30)
    assert_same(cam.lens, make_lens(COLMAP_WANT["7"], (1280, 1024)))
