"""``--from exif`` in the commands: a photo whose EXIF records its 35 mm equivalent focal length (written here by
Pillow) warps into an equirect with its centre forward and its edge columns at half its field of view, where the
equirect formula of CONVENTIONS.md (``phi = (2x/W - 1) pi``) puts them; the "not a 2:1 panorama" error offers it;
``info`` prints the spec; a photo without the tags refuses in one line with exit code 1."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

pytest.importorskip("PIL.Image")
from tests.lenses.test_exif_view import fov_formula, write_photo  # noqa: E402

def printed_fov(text: str) -> float:
    """The field of the ``perspective:fov=`` a command printed (12 significant digits)."""
    import re

    return float(re.search(r"perspective:fov=([0-9.]+)", text).group(1))


W, H, F35 = 160, 120, 28  # the photo: 4:3, a 28 mm equivalent
WO, HO = 1440, 720  # the equirect: 0.25 degree a pixel


def test_warp_from_exif_puts_the_photo_where_the_equirect_formula_says(tmp_path, capsys):
    from lenslab.io import read

    src = write_photo(tmp_path / "p.jpg", W, H, focal35=F35, quality=95)
    out = tmp_path / "pano.exr"
    assert main(["warp", str(src), "-o", str(out), "--from", "exif", "--to", "equirect",
                 "--size", f"{WO}x{HO}", "--pixel-type", "float", "-q"]) == 0
    fov = fov_formula(F35, W, H)
    assert printed_fov(capsys.readouterr().err) == pytest.approx(fov, abs=1e-9)
    pano = read(out)[0]
    row = read(src)[0][H // 2, :, 0]  # the photo's ramp as read (the same in every row: no vertical detail)
    lon = np.degrees((2 * (np.arange(WO) + 0.5) / WO - 1) * np.pi)  # the equator rows' column centres
    inside = np.abs(lon) < fov / 2
    margin = np.min(np.abs(np.abs(lon) - fov / 2))
    assert margin > 1e-3  # no column centre on the edge itself, so which side it lies is clear
    for r in (HO // 2 - 1, HO // 2):  # the rows either side of the equator (latitude +-0.125 degree)
        alpha = pano[r, :, 3]
        np.testing.assert_array_equal(alpha > 0.5, inside)  # the edges at +-fov/2, nothing beyond
        np.testing.assert_array_equal(alpha[inside], 1.0)
        # the pinhole's column of each longitude: x = W/2 (1 + tan(lon) / tan(fov/2)); the ramp read there (bilinear,
        # as the warp's default filter), to the warp map's own accuracy: 1/200 of a source pixel (lenslab.warp.maps:
        # its lattice holds 1/500, 1/350 measured), i.e. the ramp's slope there times 1/200, plus float32's 1e-6
        x = W / 2 * (1 + np.tan(np.radians(lon[inside])) / np.tan(np.radians(fov / 2)))
        expected = np.interp(x - 0.5, np.arange(W), row)
        slope = np.abs(np.interp(x - 0.5, np.arange(W - 1) + 0.5, np.diff(row)))
        assert np.all(np.abs(pano[r, inside, 0] - expected) <= slope / 200 + 1e-6)
    centre = pano[HO // 2 - 1:HO // 2 + 1, WO // 2 - 1:WO // 2 + 1, 0].mean()  # the four pixels round forward
    assert centre == pytest.approx(np.interp(W / 2 - 0.5, np.arange(W), row), abs=1e-4)
    first = int(np.argmax(inside))  # the first column inside: where the photo's left edge lands
    assert first == int(np.ceil((180 - fov / 2) / 360 * WO - 0.5))


def test_a_photo_that_is_no_panorama_is_offered_from_exif(tmp_path, capsys):
    src = write_photo(tmp_path / "p.jpg", W, H, focal35=F35, quality=95)
    code = main(["warp", str(src), "-o", str(tmp_path / "o.exr"), "--to", "equirect"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and "\n" not in err
    assert "not a 2:1 panorama" in err and "--from exif" in err
    assert printed_fov(err) == pytest.approx(fov_formula(F35, W, H), abs=1e-9)


def test_info_prints_the_spec_from_exif_and_it_parses_back(tmp_path, capsys):
    from lenslab.lenses import make_lens

    src = write_photo(tmp_path / "p.jpg", W, H, focal35=F35, orientation=6, quality=95)
    assert main(["info", str(src)]) == 0
    line = next(l for l in capsys.readouterr().out.splitlines() if "--from exif gives" in l)
    spec = line.split("--from exif gives ")[1].split()[0]
    assert make_lens(spec, (H, W)).fov == pytest.approx(fov_formula(F35, H, W), abs=1e-9)  # shown 120 x 160


def test_info_says_lensfun_auto_is_better_where_lensfun_has_the_lens(tmp_path, capsys):
    pytest.importorskip("lensfunpy")
    from tests.lenses.test_exif_lens import exif as lens_exif
    from PIL import Image

    ex = lens_exif()
    ex.get_ifd(0x8769)[0xA405] = 13  # the Samyang 8 mm on the EOS 600D (crop 1.6)
    path = tmp_path / "p.jpg"
    Image.fromarray(np.zeros((96, 144, 3), np.uint8)).save(path, exif=ex)
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "lensfun:auto uses lensfun:" in out
    assert "--from exif gives perspective:fov=" in out and "lensfun:auto is the better choice" in out


def test_a_photo_without_the_tags_refuses_from_exif_with_exit_1(tmp_path, capsys):
    src = write_photo(tmp_path / "p.jpg", W, H, focal=6.81, quality=95)
    code = main(["warp", str(src), "-o", str(tmp_path / "o.exr"), "--from", "exif", "--to", "equirect"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and "\n" not in err
    assert "FocalLengthIn35mmFilm" in err and "FocalPlaneXResolution" in err
    assert not (tmp_path / "o.exr").exists()


def test_stmap_from_exif_photo_takes_the_photos_size(tmp_path, capsys):
    from lenslab.io import read

    src = write_photo(tmp_path / "p.jpg", W, H, focal35=F35, orientation=6, quality=95)
    out = tmp_path / "map.exr"
    assert main(["stmap", "--from", f"exif:photo={src}", "--to", "equirect", "--size", "720x360", "-o",
                 str(out), "-q"]) == 0
    recorded = read(out)[1]["attributes"]["lenslab:stmap"]
    fov = fov_formula(F35, H, W)  # shown 120 x 160
    assert recorded.startswith("from perspective:fov=") and f" {H}x{W} to " in recorded
    assert printed_fov(recorded) == pytest.approx(fov, abs=1e-9)


@pytest.mark.shared_data
def test_a_real_phone_photo_is_offered_its_own_field(shared_data, tmp_path, capsys):
    """The Pixel 6 Pro's 4080 x 3072 photo (FocalLengthIn35mmFilm 24): the error names --from exif and its field, the
    formula's for a 4:3 image, and info prints the same spec."""
    photo = shared_data / "formats" / "oiio-images" / "ultrahdr_sky.jpg"
    code = main(["warp", str(photo), "-o", str(tmp_path / "o.exr"), "--to", "equirect"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and "4080x3072 is not a 2:1 panorama" in err and "--from exif" in err
    assert printed_fov(err) == pytest.approx(fov_formula(24, 4080, 3072), abs=1e-9)
    assert main(["info", str(photo)]) == 0
    line = next(l for l in capsys.readouterr().out.splitlines() if "--from exif gives" in l)
    assert printed_fov(line) == printed_fov(err)


def test_warp_from_exif_photo_of_the_photo_itself_says_nothing_of_a_crop(tmp_path, capsys):
    """exif:photo=PHOTO is checked once at a probe size before the warp: that size is no crop of the photo."""
    from tests.lenses.test_exif_view import IFDRational

    plane = (IFDRational(4000), IFDRational(4000), 3, (4000, 3000))
    src = write_photo(tmp_path / "p.jpg", W, H, focal35=F35, plane=plane, quality=95)
    assert main(["warp", str(src), "-o", str(tmp_path / "o.exr"), "--from", f"exif:photo={src}", "--to", "equirect",
                 "--size", "360x180", "-q"]) == 0
    assert "cropped" not in capsys.readouterr().err


def test_the_lens_listing_names_a_photos_own_lens(capsys):
    assert main(["lenses"]) == 0
    assert "A photo's own lens: --from exif" in capsys.readouterr().out
