"""A points file holding its header row and no point says there are no points (one line, exit 1), not that
its rows have different numbers of columns."""

from __future__ import annotations

from lenslab.cli.main import main


def test_header_only_file_has_no_points(tmp_path, capsys):
    path = tmp_path / "points.csv"
    path.write_text("x,y,dx,dy,dz\n# nothing measured yet\n")
    assert main(["fit", "points", str(path), "--model", "fisheye", "--size", "100x100"]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "no points" in lines[0] and "columns" not in lines[0], lines
