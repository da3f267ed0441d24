"""Lenses from a photo's metadata: ``lensfun:auto`` and ``--from auto`` on JPEG, PNG and TIFF files whose
EXIF or XMP the test writes (Pillow, tifffile), against the explicit spec; mount mismatches named; the
lensfun database (lensfunpy) as the oracle for what lenses and cameras exist and what fits what."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

lensfunpy = pytest.importorskip("lensfunpy")
Image = pytest.importorskip("PIL.Image")
from PIL.TiffImagePlugin import IFDRational  # noqa: E402

CAMERA_MAKE, CAMERA_MODEL = "Canon", "Canon EOS 600D"
LENS = "Samyang 8mm f/3.5 Fish-Eye CS"  # Canon EF among its mounts: fits the EF-S body
EXPLICIT = f"lensfun:lens={LENS},camera={CAMERA_MODEL},focal=8,aperture=5.6"


def pixels(h=96, w=144):
    rng = np.random.default_rng(7)
    return (rng.random((h, w, 3)) * 255).astype(np.uint8)


def exif(lens=LENS, model=CAMERA_MODEL, focal=(8, 1), fnumber=(56, 10)):
    ex = Image.Exif()
    ex[0x010F], ex[0x0110] = CAMERA_MAKE, model  # Make, Model
    sub = ex.get_ifd(0x8769)  # the Exif IFD
    sub[0xA434] = lens  # LensModel
    sub[0x920A] = IFDRational(*focal)  # FocalLength
    sub[0x829D] = IFDRational(*fnumber)  # FNumber
    return ex


def xmp_packet(lens=LENS, focal="8/1", fnumber="56/10") -> bytes:
    return (f'<?xpacket begin="" id="W5M0MpCehiHzreSzNTczkc9d"?><x:xmpmeta xmlns:x="adobe:ns:meta/">'
            f'<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description '
            f'xmlns:aux="http://ns.adobe.com/exif/1.0/aux/" xmlns:exif="http://ns.adobe.com/exif/1.0/" '
            f'aux:Lens="{lens}" exif:FocalLength="{focal}" exif:FNumber="{fnumber}"/></rdf:RDF></x:xmpmeta>'
            f'<?xpacket end="w"?>').encode()


def write_jpeg(path, **kw):
    Image.fromarray(pixels()).save(path, exif=exif(**kw), quality=95)


def write_png(path):
    Image.fromarray(pixels()).save(path, exif=exif())  # PNG's eXIf chunk


def write_tiff(path):
    """A TIFF as raw converters write them: Make and Model tags, the lens in an XMP packet (tag 700)."""
    import tifffile

    tifffile.imwrite(path, pixels(), photometric="rgb",
                     extratags=[(271, "s", 0, CAMERA_MAKE, True), (272, "s", 0, CAMERA_MODEL, True),
                                (700, "B", 0, xmp_packet(), True)])


def test_metadata_is_read_from_jpeg_png_and_tiff(tmp_path):
    from lenslab.lenses.lensfun.exif import photo_lens

    for name, write in (("a.jpg", write_jpeg), ("a.png", write_png), ("a.tif", write_tiff)):
        write(tmp_path / name)
        info = photo_lens(tmp_path / name)
        assert (info.camera, info.lens_model, info.focal, info.aperture) == (CAMERA_MODEL, LENS, 8.0, 5.6), name
    assert photo_lens(tmp_path / "a.tif").sources == ["EXIF", "XMP"]


@pytest.mark.parametrize("name,write", [("photo.jpg", write_jpeg), ("photo.tif", write_tiff)])
def test_lensfun_auto_warps_bit_for_bit_as_the_explicit_spec(tmp_path, name, write, capsys):
    src = tmp_path / name
    write(src)
    common = ["--to", "perspective:fov=90", "--size", "64x48", "-q"]
    auto, explicit = tmp_path / "auto.exr", tmp_path / "explicit.exr"
    assert main(["warp", str(src), "-o", str(auto), "--from", "lensfun:auto", *common]) == 0
    assert f"source lens from the file's metadata: {EXPLICIT}" in capsys.readouterr().err
    assert main(["warp", str(src), "-o", str(explicit), "--from", EXPLICIT, *common]) == 0
    from lenslab import io

    a, _ = io.read(str(auto))
    b, _ = io.read(str(explicit))
    assert a.tobytes() == b.tobytes() and np.isfinite(a).all() and a.std() > 0
    # --from auto: the file records no lenslab camera, so its metadata's lens
    again = tmp_path / "again.exr"
    assert main(["warp", str(src), "-o", str(again), "--from", "auto", *common]) == 0
    assert io.read(str(again))[0].tobytes() == a.tobytes()


def test_values_given_with_auto_win_over_the_files(tmp_path, capsys):
    from lenslab.lenses.lensfun.match import auto_spec

    write_jpeg(tmp_path / "p.jpg")
    assert auto_spec("lensfun:auto,aperture=11", tmp_path / "p.jpg") == EXPLICIT.replace("aperture=5.6", "aperture=11")


def test_a_mount_mismatch_names_the_mounts_the_camera_and_the_way_out(tmp_path, capsys):
    """The Samyang 8mm f/2.8 UMC is a mirrorless lens (lensfun: Sony E, Fujifilm X, Samsung NX); the
    EOS 600D is a Canon EF-S body: lensfun does not pair them, and the message says why once."""
    db = lensfunpy.Database()
    cam = db.find_cameras(CAMERA_MAKE, CAMERA_MODEL)[0]
    umc = [l for l in db.lenses if l.model == "Samyang 8mm f/2.8 UMC Fish-eye"][0]
    assert cam.mount == "Canon EF-S" and "Canon EF-S" not in umc.mounts  # the oracle's facts
    assert not db.find_lenses(cam, None, "Samyang 8mm f/2.8 UMC")
    src = tmp_path / "umc.jpg"
    write_jpeg(src, lens=umc.model)
    code = main(["warp", str(src), "-o", str(tmp_path / "o.exr"), "--from", "lensfun:auto",
                 "--to", "perspective:fov=90", "--size", "32x24", "-q"])
    err = capsys.readouterr().err
    assert code == 1 and err.count("\n") == 1
    assert f"the lens has mounts {', '.join(umc.mounts)}; the Canon EOS 600D is Canon EF-S with crop " \
           f"{cam.crop_factor:.4g}" in err
    assert f"crop={cam.crop_factor:.4g}" in err and "camera=" in err and "Canon Canon" not in err
    # the explicit spec says the same (a spec the user typed that cannot work: a usage error, 2)
    code = main(["warp", str(src), "-o", str(tmp_path / "o.exr"), "--from",
                 f"lensfun:lens={umc.model},camera=Canon EOS 600D", "--to", "perspective:fov=90", "--size", "32x24",
                 "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "the lens has mounts" in err and "Canon Canon" not in err


def test_info_shows_the_lens_found_and_the_profile(tmp_path, capsys):
    write_jpeg(tmp_path / "p.jpg")
    assert main(["info", str(tmp_path / "p.jpg")]) == 0
    out = capsys.readouterr().out
    assert f"lens in metadata: {CAMERA_MODEL}, {LENS}, 8 mm, f/5.6 (EXIF)" in out
    assert f"lensfun:auto uses {EXPLICIT}" in out


def test_lensfun_search_lists_lenses_then_only_cameras_that_fit_them(capsys):
    assert main(["lenses", "--lensfun", "canon 24-105"]) == 0
    out = capsys.readouterr().out
    db = lensfunpy.Database()
    want = {l.model for l in db.lenses if "24-105" in l.model and l.maker == "Canon"}
    shown = {line.split(": ", 1)[1] for line in out.splitlines() if line.startswith("Canon: ")}
    assert want <= shown
    cams = [line for line in out.splitlines() if line.startswith("  ") and "mount" in line]
    assert len(cams) < 10  # no list of every Canon body
    assert main(["lenses", "--lensfun", "eos 600d"]) == 0
    out = capsys.readouterr().out
    assert "Canon EOS 600D" in out and out.count("mount ") == 1


def test_exr_standard_attributes_name_the_lens(tmp_path, capsys):
    """OpenEXR's standard camera and lens attributes, written by the OpenEXR bindings."""
    OpenEXR = pytest.importorskip("OpenEXR")
    from lenslab.lenses.lensfun.match import auto_spec

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "cameraMake": CAMERA_MAKE,
              "cameraModel": CAMERA_MODEL, "lensModel": LENS, "nominalFocalLength": 8.0, "aperture": 5.6,
              "focus": 3.0}
    path = tmp_path / "shot.exr"
    OpenEXR.File(header, {"RGB": np.full((24, 36, 3), 0.5, np.float32)}).write(str(path))
    assert auto_spec("lensfun:auto", path) == EXPLICIT + ",distance=3"
    assert main(["info", str(path)]) == 0
    assert f"lensfun:auto uses {EXPLICIT},distance=3" in capsys.readouterr().out


def test_a_photo_without_a_lens_or_with_garbage_exif_says_so_in_one_line(tmp_path, capsys):
    from lenslab.lenses.lensfun.exif import photo_lens

    bare = tmp_path / "bare.jpg"
    Image.fromarray(pixels()).save(bare, quality=90)
    junk = tmp_path / "junk.jpg"  # an APP1 Exif segment whose IFD points past the file's end
    data = bare.read_bytes()
    junk.write_bytes(data[:2] + b"\xff\xe1\x00\x16Exif\x00\x00II*\x00\xff\xff\xff\x7f\x00\x00\x00\x00" + data[2:])
    assert photo_lens(junk).lens_model is None
    for path in (bare, junk):
        code = main(["warp", str(path), "-o", str(tmp_path / "o.exr"), "--from", "lensfun:auto",
                     "--to", "perspective:fov=90", "--size", "32x24", "-q", "--overwrite"])
        err = capsys.readouterr().err
        assert code == 1 and err.count("\n") == 1  # the junk one: the JPEG reader's own one line
        assert path == junk or "records no lens model" in err
