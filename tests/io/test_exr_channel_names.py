"""EXR channel names: only a channel named ``A`` (or ``layer.A``) is alpha, and names go from input to output.

The files are made with the OpenEXR bindings; what lenslab writes is read back with OpenImageIO, the
reader compositors share, for its channel names, its alpha channel (``spec.alpha_channel``, -1: none)
and its values. Values are compared bit for bit: a float file converted to float EXR, and a half file
to half EXR, copy every sample (no tolerance is needed, none is given).
"""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")

H, W = 8, 16


def _header(**extra):
    return {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, **extra}


def _uv():
    u = np.linspace(0.0, 5.0, H * W, dtype=np.float32).reshape(H, W)  # as the user's u: 0..5
    v = np.linspace(-5.0, 5.0, H * W, dtype=np.float32).reshape(H, W)[::-1].copy()  # v: -5..5
    return u, v


def _oiio(path, subimage=0):
    """(channel names, alpha channel index, float32 pixels H x W x C) as OpenImageIO reads ``path``."""
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    try:
        assert inp.seek_subimage(subimage, 0)
        spec = inp.spec()
        pixels = inp.read_image(subimage, 0, 0, spec.nchannels, "float")
        return tuple(spec.channelnames), spec.alpha_channel, np.asarray(pixels, np.float32).reshape(
            spec.height, spec.width, spec.nchannels)
    finally:
        inp.close()


def test_two_data_channels_read_as_data(tmp_path):
    u, v = _uv()
    OpenEXR.File(_header(), {"u": u, "v": v}).write(str(tmp_path / "uv.exr"))
    names, alpha, _ = _oiio(tmp_path / "uv.exr")
    assert names == ("u", "v") and alpha == -1  # the oracle: two data channels, no alpha
    image, meta = lio.read(tmp_path / "uv.exr")
    assert meta["channels"] == ["u", "v"] and meta["channel_names"] == ["u", "v"]
    assert not any(lio.is_alpha_name(n) for n in meta["channel_names"])
    np.testing.assert_array_equal(image[..., 0], u)
    np.testing.assert_array_equal(image[..., 1], v)  # -5..5 as stored, not clipped


def test_convert_keeps_data_channels_and_their_names(tmp_path):
    u, v = _uv()
    OpenEXR.File(_header(), {"u": u, "v": v}).write(str(tmp_path / "uv.exr"))
    assert main(["convert", str(tmp_path / "uv.exr"), "--to", "exr", "-o", str(tmp_path / "out.exr"), "-q"]) == 0
    names, alpha, pixels = _oiio(tmp_path / "out.exr")
    assert names == ("u", "v")
    assert alpha == -1  # a compositor sees no alpha
    np.testing.assert_array_equal(pixels[..., 0], u)
    np.testing.assert_array_equal(pixels[..., 1], v)


@pytest.mark.parametrize("name", ["G", "Z"])
def test_convert_keeps_a_lone_channel_name(tmp_path, name):
    u, _ = _uv()
    OpenEXR.File(_header(), {name: u}).write(str(tmp_path / "one.exr"))
    assert main(["convert", str(tmp_path / "one.exr"), "--to", "exr", "-o", str(tmp_path / "out.exr"), "-q"]) == 0
    names, alpha, pixels = _oiio(tmp_path / "out.exr")
    assert names == (name,) and alpha == -1
    np.testing.assert_array_equal(pixels[..., 0], u)


def test_convert_part_with_a_layer_keeps_layer_names(tmp_path):
    """A part whose only layer is ``forward`` (as in OpenEXR's multipart sample): ``forward.u``,
    ``forward.v`` with values from -41.75 to 0 come out under those names, not as grey and alpha."""
    u, v = _uv()
    fu = (-41.75 * u / 5.0).astype(np.float16)
    fv = (-41.75 * (v + 5.0) / 10.0).astype(np.float16)
    rgba = {c: np.full((H, W), 0.5, np.float16) for c in "RGBA"}
    parts = [OpenEXR.Part(_header(name="rgba_left"), rgba),
             OpenEXR.Part(_header(name="forward_left"), {"forward.u": fu, "forward.v": fv})]
    OpenEXR.File(parts).write(str(tmp_path / "multipart.exr"))
    names, alpha, src = _oiio(tmp_path / "multipart.exr", 1)
    assert names == ("forward.u", "forward.v") and alpha == -1
    assert main(["convert", f"{tmp_path / 'multipart.exr'}:forward_left", "--to", "exr", "-o",
                 str(tmp_path / "f.exr"), "-q"]) == 0
    names, alpha, pixels = _oiio(tmp_path / "f.exr")
    assert names == ("forward.u", "forward.v") and alpha == -1
    np.testing.assert_array_equal(pixels, src)  # half in, half out: every sample as OpenImageIO read it
    assert pixels.min() == -41.75 and pixels.max() == 0.0


def test_alpha_named_A_stays_alpha(tmp_path):
    u, _ = _uv()
    a = np.linspace(0.0, 1.0, H * W, dtype=np.float32).reshape(H, W)
    OpenEXR.File(_header(), {"Y": u * a, "A": a}).write(str(tmp_path / "ya.exr"))
    assert main(["convert", str(tmp_path / "ya.exr"), "--to", "exr", "-o", str(tmp_path / "out.exr"), "-q"]) == 0
    names, alpha, pixels = _oiio(tmp_path / "out.exr")
    assert names == ("Y", "A") and alpha == 1
    np.testing.assert_array_equal(pixels[..., 1], a)


def test_warp_adds_coverage_as_A_beside_a_named_channel(tmp_path):
    """A one-channel ``Z`` warped keeps its name; the coverage the warp adds is the alpha ``A``."""
    u, _ = _uv()
    OpenEXR.File(_header(), {"Z": u}).write(str(tmp_path / "z.exr"))
    assert main(["warp", str(tmp_path / "z.exr"), "-o", str(tmp_path / "w.exr"), "--from", "equirect",
                 "--to", "equirect", "--size", f"{W}x{H}", "--pixel-type", "float", "-q"]) == 0
    names, alpha, pixels = _oiio(tmp_path / "w.exr")
    assert sorted(names) == ["A", "Z"] and names[alpha] == "A"  # EXR lists channels in name order
    z = pixels[..., names.index("Z")]
    assert z.max() > 1.0  # the data channel is not clipped to [0, 1]
    image, meta = lio.read(tmp_path / "w.exr")
    assert meta["channels"] == ["Z", "A"]  # read back: alpha last, as lenslab holds it
    np.testing.assert_array_equal(image[..., 0], z)
    np.testing.assert_array_equal(image[..., 1], pixels[..., alpha])


def test_output_channels_rules():
    assert lio.output_channels({"channel_names": ["forward.u", "forward.v"]}, 2) == ["forward.u", "forward.v"]
    assert lio.output_channels({"channels": ["R", "G", "B"]}, 4) == ["R", "G", "B", "A"]
    assert lio.output_channels({"channels": ["Y", "A"]}, 3) == ["R", "G", "B"]  # had alpha: no second A
    assert lio.output_channels({}, 2) == ["Y", "A"]
    assert lio.is_alpha_name("left.A") and not lio.is_alpha_name("AO") and not lio.is_alpha_name("v")


def test_carries_alpha_follows_the_names_openimageio_reads(tmp_path):
    u, v = _uv()
    for name, chans in {"uv": {"u": u, "v": v}, "ya": {"Y": u, "A": np.clip(v, 0, 1)},
                        "layer": {"left.R": u, "left.G": u, "left.B": u, "left.A": np.clip(v, 0, 1)}}.items():
        OpenEXR.File(_header(), chans).write(str(tmp_path / f"{name}.exr"))
        names, alpha, _ = _oiio(tmp_path / f"{name}.exr")
        image, meta = lio.read(tmp_path / f"{name}.exr")
        assert lio.carries_alpha(meta, image.shape[2]) == (alpha >= 0), name


def test_settle_leaves_data_channels_alone():
    """``settle`` with ``alpha=False`` (two data channels): nothing clipped, nothing divided; the coverage
    alone is clipped. With alpha (the default for 2 channels) the rules of lenslab.io.alpha apply."""
    from lenslab.io.alpha import settle, split_alpha

    u, v = _uv()
    image = np.stack([u, v], axis=-1)
    coverage = np.full((H, W), 1.5, np.float32)
    data = image.copy()
    settle(data, coverage, alpha=False)
    np.testing.assert_array_equal(data, image)
    assert coverage.max() == 1.0
    colour, a = split_alpha(data, coverage, alpha=False)
    assert colour.shape == (H, W, 2) and a is coverage
    as_alpha = image.copy()
    settle(as_alpha, None)
    assert as_alpha[..., 1].min() >= 0.0 and as_alpha[..., 1].max() <= 1.0  # v taken as alpha: settled
