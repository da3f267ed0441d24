"""Mistakes on the command line are usage errors (exit 2, one line, nothing written or read); an input
that cannot be read is a failed input (exit 1) named with the operating system's reason, no errno."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


@pytest.fixture
def three(tmp_path):
    paths = []
    for i in range(3):
        p = tmp_path / f"in{i}.exr"
        write(p, np.full((8, 16, 3), 0.25 * (i + 1), np.float32))
        paths.append(str(p))
    return paths


@pytest.mark.parametrize("command", [["warp", "--to", "fisheye:fov=180", "--size", "8x8"], ["convert", "--to", "png"],
                                     ["tonemap", "--format", "jpg"]])
def test_a_file_name_for_several_outputs_is_a_usage_error_and_makes_no_folder(three, tmp_path, capsys, command):
    out = tmp_path / "several.exr"
    rc = main([command[0], *three, "-o", str(out), *command[1:]])
    err = capsys.readouterr().err
    assert rc == 2 and "names a file but there are 3 inputs" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_an_unknown_output_extension_is_refused_before_the_input_is_read(tmp_path, capsys):
    rc = main(["tonemap", str(tmp_path / "not-there.exr"), "-o", str(tmp_path / "out.xyz")])
    err = capsys.readouterr().err
    assert rc == 2 and "cannot tell the output format from the extension '.xyz'" in err and "not-there" not in err


def test_a_folder_given_as_the_output_file_is_a_usage_error(three, tmp_path, capsys):
    folder = tmp_path / "folder"
    folder.mkdir()
    rc = main(["compare-tones", three[0], "-o", str(folder)])
    assert rc == 2 and "is a folder" in capsys.readouterr().err


@pytest.mark.parametrize("argv", [["warp", "{src}", "-o", "{out}"],  # neither --to nor --stmap
                                  ["warp", "{src}", "-o", "{out}", "--to", "fisheye", "--look-at", "0,0,1", "--yaw", "5"]])
def test_warp_option_conflicts_are_usage_errors(three, tmp_path, capsys, argv):
    out = tmp_path / "o.exr"
    assert main([a.format(src=three[0], out=out) for a in argv]) == 2
    assert not out.exists()


@pytest.mark.parametrize("command", [["tonemap", "-o", "{tmp}/x.jpg"], ["convert", "--to", "png", "-o", "{tmp}/x.png"],
                                     ["warp", "--to", "fisheye", "-o", "{tmp}/x.exr"]])
def test_a_missing_input_is_named_with_the_reason_and_no_errno(tmp_path, capsys, command):
    missing = tmp_path / "nosuch.exr"
    rc = main([command[0], str(missing)] + [a.format(tmp=tmp_path) for a in command[1:]])
    err = capsys.readouterr().err
    assert rc == 1 and f"{missing}: no such file or directory" in err and "Errno" not in err


def test_skip_existing_counts_the_outputs_left_alone(three, tmp_path, capsys):
    out = tmp_path / "pngs"
    assert main(["convert", *three, "--to", "png", "-o", str(out)]) == 0
    capsys.readouterr()
    assert main(["convert", *three, "--to", "png", "-o", str(out), "--skip-existing"]) == 0
    assert "converted 0 of 3 file(s) to PNG; 3 already there, left alone" in capsys.readouterr().err


@pytest.mark.parametrize("look, pitch", [("0,1,0", "90"), ("0,-2,0", "-90")])
def test_looking_straight_up_or_down_is_the_pitch_pose(tmp_path, look, pitch):
    # the help's own example, --look-at 0,1,0: "up" gives no direction there, so the view is --pitch's
    from lenslab.io import read

    pano = tmp_path / "pano.exr"
    write(pano, np.random.default_rng(0).uniform(0, 1, (32, 64, 3)).astype(np.float32))
    common = [str(pano), "--to", "perspective:fov=90", "--size", "16x16", "-q"]
    assert main(["warp", *common, "-o", str(tmp_path / "look.exr"), "--look-at", look]) == 0
    assert main(["warp", *common, "-o", str(tmp_path / "pitch.exr"), "--pitch", pitch]) == 0
    looked = read(tmp_path / "look.exr")[0]
    np.testing.assert_array_equal(looked, read(tmp_path / "pitch.exr")[0])
    assert main(["warp", *common, "-o", str(tmp_path / "level.exr")]) == 0
    assert not np.array_equal(looked, read(tmp_path / "level.exr")[0])  # a view that differs from the level one


def test_compare_tones_refuses_an_unknown_extension_before_reading(tmp_path, capsys):
    rc = main(["compare-tones", str(tmp_path / "not-there.exr"), "-o", str(tmp_path / "strip.xyz")])
    assert rc == 2 and "cannot tell the output format" in capsys.readouterr().err


def test_tonemap_of_one_file_skips_an_existing_output(three, tmp_path, capsys):
    out = tmp_path / "one.png"
    assert main(["tonemap", three[0], "-o", str(out)]) == 0
    before = out.read_bytes()
    assert main(["tonemap", three[1], "-o", str(out), "--skip-existing"]) == 0
    assert "left alone (--skip-existing)" in capsys.readouterr().err and out.read_bytes() == before


@pytest.mark.parametrize("command", [["tonemap"], ["convert", "--to", "png"], ["warp", "--to", "fisheye"]])
def test_a_missing_input_makes_no_output_folder(tmp_path, capsys, command):
    out = tmp_path / "new-folder"
    rc = main([command[0], str(tmp_path / "nosuch.exr"), "-o", f"{out}/", *command[1:]])
    assert rc == 1 and "nosuch.exr: no such file or directory" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("command", [["tonemap"], ["convert", "--to", "png"], ["warp", "--to", "fisheye"]])
def test_skip_existing_with_overwrite_is_a_usage_error(three, tmp_path, capsys, command):
    out = tmp_path / "out"
    rc = main([command[0], *three, "-o", str(out), *command[1:], "--skip-existing", "--overwrite"])
    assert rc == 2 and "give one" in capsys.readouterr().err and not out.exists()


def test_a_folder_in_the_place_of_one_batch_output_fails_that_file_in_plain_words(three, tmp_path, capsys):
    out = tmp_path / "pngs"
    (out / "in0.png").mkdir(parents=True)
    rc = main(["convert", *three, "--to", "png", "-o", str(out)])
    err = capsys.readouterr().err
    # an error of the output names the output alone, as every command does
    assert rc == 1 and f"lenslab convert: error: {out / 'in0.png'}: is a folder; give a file name to write to" \
        in err.splitlines()
    assert "UsageError" not in err
    assert (out / "in1.png").is_file() and (out / "in2.png").is_file()
