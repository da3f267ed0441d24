"""A photo's own lens from its EXIF (``--from exif``): the field of view of its 35 mm equivalent focal length,
against the CIPA/Exif definition transcribed here in float64 (a 36 x 24 mm frame matched by the diagonal,
hypot(36, 24) = 43.27 mm), published pairs, and the pinhole of a sensor of known size; JPEG (Pillow writes the
EXIF), turned JPEG (Orientation 6) and HEIC (pillow-heif)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab.errors import LensError
from lenslab.lenses import make_lens
from lenslab.lenses.exif_view import exif_view, horizontal_fov

Image = pytest.importorskip("PIL.Image")
from PIL.TiffImagePlugin import IFDRational  # noqa: E402

D35 = np.hypot(np.float64(36.0), np.float64(24.0))  # the 35 mm frame's diagonal, mm (43.2666)

def view_of(path, size, **kw):
    """The photo lens of ``path`` shown at ``size``, its stored frame read from its header as the commands do."""
    from lenslab.io.exif_orientation import stored_size

    return exif_view(path, size, stored_size(path, size), **kw)


def fov_formula(f35, w, h) -> float:
    """The field across the width of a w x h image whose diagonal sees what a 36 x 24 mm frame's does at f35."""
    half_diag = np.arctan(D35 / (2.0 * np.float64(f35)))
    return float(np.degrees(2.0 * np.arctan(np.tan(half_diag) * w / np.hypot(np.float64(w), np.float64(h)))))


def write_photo(path, w=160, h=120, focal35=None, focal=None, plane=None, orientation=None, **save):
    """A photo whose EXIF Pillow writes: FocalLengthIn35mmFilm (0xA405), FocalLength (0x920A), the focal plane
    resolution (0xA20E, 0xA20F, unit 0xA210) and frame (0xA002, 0xA003), Orientation (0x0112)."""
    codes = np.zeros((h, w, 3), np.uint8)
    codes[..., 0] = np.round(np.linspace(0, 255, w))[None, :]
    ex = Image.Exif()
    ex[0x010F], ex[0x0110] = "Google", "Pixel 6 Pro"
    if orientation:
        ex[0x0112] = orientation
    sub = ex.get_ifd(0x8769)
    if focal35 is not None:
        sub[0xA405] = focal35
    if focal is not None:
        sub[0x920A] = IFDRational(round(focal * 100), 100)
    if plane is not None:
        xres, yres, unit, frame = plane
        sub[0xA20E], sub[0xA20F], sub[0xA210] = IFDRational(xres), IFDRational(yres), unit
        if frame:
            sub[0xA002], sub[0xA003] = frame
    Image.fromarray(codes).save(path, exif=ex, **save)
    return path


def test_published_pair_24mm():
    """A 24 mm equivalent sees 84.1 degrees across the diagonal and 73.7 across a 3:2 frame (the figures lens makers
    publish for 24 mm on full frame; given to 0.1 degree, so they hold to 0.05)."""
    from lenslab.lenses.exif_view import diagonal_fov

    assert diagonal_fov(24.0) == pytest.approx(84.1, abs=0.05)
    assert horizontal_fov(24.0, 6000, 4000) == pytest.approx(73.7, abs=0.05)
    assert horizontal_fov(24.0, 6000, 4000) == pytest.approx(math.degrees(2 * math.atan(18 / 24)), abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.floats(1.0, 65535.0), st.integers(16, 8192), st.integers(16, 8192))
def test_the_printed_spec_parses_back_to_the_formulas_field(f35, w, h):
    """The spec ``--from exif`` gives is a perspective lens whose edge column looks at half the formula's field and
    whose corner at half the 35 mm frame's diagonal field (float64 formulas here)."""
    from lenslab.lenses.exif_view import ExifView

    view = ExifView(f35, "FocalLengthIn35mmFilm", (w, h))
    lens = make_lens(view.spec, (w, h))
    assert view.spec.startswith("perspective:fov=")
    d, ok = lens.pixel_to_dir(np.array([[0.0, h / 2], [0.0, 0.0]]))
    assert ok.all()
    edge = np.degrees(np.arctan2(-d[0, 0], d[0, 2]))
    corner = np.degrees(np.arccos(d[1, 2] / np.linalg.norm(d[1])))
    assert edge == pytest.approx(fov_formula(f35, w, h) / 2, abs=1e-8)
    # the spec keeps 12 digits of fov (5e-10 degree); the corner moves at most hypot(1, h/w) times as much as the
    # edge; 1e-8 leaves room for the lens's own float64 steps
    assert corner == pytest.approx(np.degrees(np.arctan(D35 / (2 * f35))), abs=1e-8 * (1 + h / w))


@pytest.mark.parametrize("name", ["p.jpg", "p.png"])
def test_focal_length_in_35mm_film(tmp_path, name):
    """JPEG's APP1 and PNG's eXIf chunk, as Pillow writes them."""
    path = write_photo(tmp_path / name, 160, 120, focal35=24, focal=6.81)
    view = view_of(path, (160, 120))
    assert view.focal35 == 24
    assert view.fov == pytest.approx(fov_formula(24, 160, 120), abs=1e-12)


def test_a_portrait_photo_gives_the_narrower_field_across(tmp_path):
    """Orientation 6: a 160 x 120 landscape sensor image shown 120 x 160; its field across is the narrower one."""
    from lenslab.io import read

    path = write_photo(tmp_path / "p.jpg", 160, 120, focal35=26, orientation=6, quality=95)
    shown = tuple(read(path)[1]["size"])
    assert shown == (120, 160)
    view = view_of(path, shown)
    assert view.fov == pytest.approx(fov_formula(26, 120, 160), abs=1e-12)
    assert view.fov < fov_formula(26, 160, 120) - 10


def test_focal_plane_resolution_gives_the_sensor_pinhole(tmp_path):
    """No FocalLengthIn35mmFilm: FocalLength 6.81 mm on a 9.6 x 7.2 mm sensor (4000 x 3000 pixels at 4000/0.96
    pixels per cm) sees 2 atan(4.8 / 6.81) across: the pinhole's own formula, no 35 mm frame in it."""
    plane = (IFDRational(400000, 96), IFDRational(300000, 72), 3, (4000, 3000))
    path = write_photo(tmp_path / "p.jpg", 160, 120, focal=6.81, plane=plane, quality=95)
    view = view_of(path, (160, 120))  # the file is a 160 x 120 copy of the 4000 x 3000 frame
    assert view.fov == pytest.approx(math.degrees(2 * math.atan(4.8 / 6.81)), abs=1e-9)
    assert view.focal35 == pytest.approx(6.81 * float(D35) / 12.0, rel=1e-12)


def test_focal_plane_in_inches_by_default_and_the_image_as_the_frame(tmp_path):
    """Unit 2 (inches, Exif's default) and no PixelXDimension: the image itself is the frame."""
    plane = (IFDRational(160 * 254, 96), IFDRational(120 * 254, 72), 2, None)  # 160 px over 9.6 mm
    path = write_photo(tmp_path / "p.jpg", 160, 120, focal=6.81, plane=plane, quality=95)
    assert view_of(path, (160, 120)).fov == pytest.approx(math.degrees(2 * math.atan(4.8 / 6.81)), abs=1e-9)


def test_heic_exif(tmp_path):
    pillow_heif = pytest.importorskip("pillow_heif")
    pillow_heif.register_heif_opener()
    path = write_photo(tmp_path / "p.heic", 160, 120, focal35=26, focal=5.1, quality=90)
    assert view_of(path, (160, 120)).fov == pytest.approx(fov_formula(26, 160, 120), abs=1e-12)


@pytest.mark.parametrize("tags, missing", [
    ({}, "no FocalLengthIn35mmFilm nor FocalLength"),
    ({"focal": 6.81}, "nor FocalPlaneXResolution to go with FocalLength 6.81 mm"),
    ({"focal": 6.81, "plane": (IFDRational(400), IFDRational(400), 1, None)}, "FocalPlaneResolutionUnit 1 is no length"),
])
def test_a_photo_without_the_tags_refuses_in_one_line_naming_them(tmp_path, tags, missing):
    path = write_photo(tmp_path / "p.jpg", **tags)
    with pytest.raises(LensError) as err:
        view_of(path, (160, 120))
    text = str(err.value)
    assert "\n" not in text and missing in text and str(path) in text


def test_exif_photo_spec_reads_the_named_photo(tmp_path):
    """``exif:photo=PATH`` (stmap's --from) is the same lens; plain ``exif`` names no photo."""
    path = write_photo(tmp_path / "p.jpg", 160, 120, focal35=24, quality=95)
    lens = make_lens(f"exif:photo={path}", (160, 120))
    assert lens.fov == pytest.approx(fov_formula(24, 160, 120), abs=1e-6)
    with pytest.raises(LensError, match="exif:photo=PHOTO"):
        make_lens("exif", (160, 120))


def test_a_photo_of_another_shape_than_its_recorded_frame_is_noted_as_cropped(tmp_path):
    """A 160 x 160 image whose EXIF records a 4000 x 3000 frame was cropped: the field is noted as too wide; a
    160 x 120 copy of that frame (the same shape) is not noted."""
    plane = (IFDRational(4000), IFDRational(4000), 3, (4000, 3000))
    square = write_photo(tmp_path / "sq.jpg", 160, 160, focal35=24, plane=plane, quality=95)
    with pytest.warns(UserWarning, match="4000x3000 frame: it looks cropped"):
        view_of(square, (160, 160))
    copy = write_photo(tmp_path / "copy.jpg", 160, 120, focal35=24, plane=plane, quality=95)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        view_of(copy, (160, 120))
        view_of(copy, (120, 160))  # turned by its orientation


def test_xmp_alone_gives_it_too(tmp_path):
    """A TIFF as raw converters write it: the focal length only in an XMP packet (tag 700)."""
    import tifffile

    xmp = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
           '<rdf:Description xmlns:exif="http://ns.adobe.com/exif/1.0/" exif:FocalLengthIn35mmFilm="35" '
           'exif:FocalLength="23/1"/></rdf:RDF></x:xmpmeta>').encode()
    path = tmp_path / "p.tif"
    tifffile.imwrite(path, np.zeros((120, 160, 3), np.uint8), photometric="rgb", extratags=[(700, "B", 0, xmp, True)])
    assert view_of(path, (160, 120)).fov == pytest.approx(fov_formula(35, 160, 120), abs=1e-12)


def test_a_zero_focal_length_in_35mm_film_is_unknown(tmp_path):
    """Exif: FocalLengthIn35mmFilm 0 means unknown, so the focal plane gives the field."""
    plane = (IFDRational(400000, 96), IFDRational(300000, 72), 3, (4000, 3000))
    path = write_photo(tmp_path / "p.jpg", 160, 120, focal35=0, focal=6.81, plane=plane, quality=95)
    assert view_of(path, (160, 120)).fov == pytest.approx(math.degrees(2 * math.atan(4.8 / 6.81)), abs=1e-9)


def _xmp_photo(path, props: dict):
    xmp = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
           '<rdf:Description xmlns:exif="http://ns.adobe.com/exif/1.0/" '
           + " ".join(f'exif:{k}="{v}"' for k, v in props.items()) + "/></rdf:RDF></x:xmpmeta>")
    Image.fromarray(np.zeros((100, 150, 3), np.uint8)).save(path, xmp=xmp.encode())
    return path


@pytest.mark.parametrize("props", [
    {"FocalLengthIn35mmFilm": "1e-300"},  # gave perspective:fov=180, which the lens refused without the photo's name
    {"FocalLengthIn35mmFilm": "0.5"},
    {"FocalLengthIn35mmFilm": "1e300"},  # gave perspective:fov=2.06e-297
    {"FocalLengthIn35mmFilm": "70000"},
    {"FocalLength": "1e308", "FocalPlaneXResolution": "1", "FocalPlaneResolutionUnit": "4"},  # gave fov=0
])
def test_an_equivalent_beyond_exifs_range_is_refused_naming_the_photo(tmp_path, props):
    """Exif's FocalLengthIn35mmFilm is a SHORT: 1 to 65535 mm. Beyond it (from XMP, or FocalLength over the focal
    plane), the one-line refusal names the photo and the equivalent."""
    path = _xmp_photo(tmp_path / "p.jpg", props)
    with pytest.raises(LensError) as err:
        view_of(path, (150, 100))
    text = str(err.value)
    assert "\n" not in text and str(path) in text and "35 mm equivalent" in text


@pytest.mark.parametrize("f35", ["1", "65535", "26.5"])
def test_the_ends_of_exifs_range_are_read(tmp_path, f35):
    """The field across a 3:2 image: 2 atan(18 / f35), the 36 mm side of the 35 mm frame (float64 here)."""
    path = _xmp_photo(tmp_path / "p.jpg", {"FocalLengthIn35mmFilm": f35})
    assert view_of(path, (150, 100)).fov == pytest.approx(np.degrees(2 * np.arctan(18.0 / float(f35))), abs=1e-9)


def test_info_says_why_not_where_it_printed_a_spec_that_fails(tmp_path, capsys):
    from lenslab.cli.main import main

    path = _xmp_photo(tmp_path / "p.jpg", {"FocalLengthIn35mmFilm": "1e-300"})
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "perspective:fov=180" not in out and "35 mm equivalent" in out


@pytest.mark.parametrize("size", [(150, 100), (75, 50), (300, 200), (1500, 1000)])
def test_the_focal_plane_is_the_photos_own_frame_at_any_size_asked(tmp_path, size):
    """``exif:photo=PHOTO`` at another size than the photo's (a map's, a warp's check): the sensor is still the
    photo's 150 x 100 pixels over 150 px per 9.6 mm, a 9.6 x 6.4 mm sensor, so FocalLength 6.81 mm sees
    2 atan(4.8 / 6.81) across a 3:2 image at any size (it gave 38.8 degrees at 75 x 50 and 109.3 at 300 x 200)."""
    plane = (IFDRational(round(150 / 9.6 * 25.4 * 1000), 1000),) * 2 + (2, None)
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=6.81, plane=plane, quality=95)
    fov = make_lens(f"exif:photo={path}", size).fov
    assert fov == pytest.approx(math.degrees(2 * math.atan(4.8 / 6.81)), abs=1e-9)  # (the spec's 12 digits)
