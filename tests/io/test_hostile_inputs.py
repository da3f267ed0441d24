"""Hostile inputs: every case of the corpus (lenslab.bench.hostile) is refused by the command in one
line naming the file, with exit status 1 or 2, no traceback, nothing left in the output folder, under
an address-space limit far below what the file declares (a 302-byte TIFF declaring 20000 x 20000
float RGB would take 4.8 GB), and with a peak resident memory at most 200 MB beyond that of
``lenslab info --formats`` (the interpreter and the modules every command loads): the aim "no input
under 1 MB makes any command allocate more than 200 MB". The corpus holds a valid flat-colour file of
every compressed format (lenslab.bench.bombs) that would decode to hundreds of MB."""

from __future__ import annotations

import sys

import pytest

from lenslab.bench.hostile import cases
from tests.hostile_run import run

def _case_names() -> dict:
    """The corpus's cases by name (written once into a folder removed at once: collection leaves nothing)."""
    import tempfile

    with tempfile.TemporaryDirectory(prefix="lenslab-corpus-names-") as folder:
        return {c.name: c for c in cases(folder)}


CASES = _case_names()


#: the aim: no input under 1 MB makes a command allocate more than this beyond the baseline
AIM_MB = 200.0


@pytest.fixture(scope="module")
def baseline_mb() -> float:
    done = run([sys.executable, "-m", "lenslab", "info", "--formats"])
    assert done.returncode == 0, done.stderr
    return done.peak_mb


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("corpus")
    cases(folder)
    return folder


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_file_is_refused_in_one_line(corpus, baseline_mb, tmp_path, name):
    case = CASES[name]
    out = tmp_path / "out"
    out.mkdir()
    file = case.file if case.file.startswith("/") else str(corpus / case.file)
    argv = [a.format(file=file, src=str(corpus / "src.exr"), out=str(out)) for a in case.argv]
    before = set(p.name for p in corpus.iterdir())
    done = run([sys.executable, "-m", "lenslab", *argv], cwd=tmp_path)
    assert done.returncode in (1, 2), (done.returncode, done.stderr[-500:])
    assert "Traceback" not in done.stderr
    if case.file.startswith("/") or (corpus / case.file).stat().st_size < 1 << 20:
        assert done.peak_mb - baseline_mb <= AIM_MB, (done.peak_mb, baseline_mb)
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    named = [line for line in lines if file in line]
    assert len(named) == 1, lines
    assert case.cause.lower() in named[0].lower(), named[0]
    assert len(named[0]) < 400
    assert list(out.iterdir()) == []  # no output, no temporary, no empty folder
    assert set(p.name for p in corpus.iterdir()) == before
    assert [p for p in tmp_path.iterdir() if p.name != "out"] == []


def test_ply_header_declaring_4e9_vertices_is_refused_before_vtk(tmp_path):
    """VTK allocates what a PLY header declares (and crashes); the header's counts are checked against the
    file's 180 bytes first."""
    scene = tmp_path / "bomb.ply"
    scene.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                      b"property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                      b"end_header\n" + bytes(16))
    done = run([sys.executable, "-c", "import sys; from tracer.cli import main; sys.exit(main())", "render",
                "--scene", str(scene), "-o", str(tmp_path / "r.exr")], cwd=tmp_path)
    assert done.returncode in (1, 2), done.stderr[-500:]
    assert "Traceback" not in done.stderr
    named = [line for line in done.stderr.splitlines() if str(scene) in line]
    assert len(named) == 1 and "declares" in named[0], done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bomb.ply"]
