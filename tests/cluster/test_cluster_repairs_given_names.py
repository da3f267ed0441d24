"""The one line on slight negatives of a batch run on a Dask cluster names its file as the command was given it, as a
run on this machine does: a worker of several threads hands back its process's tally with whichever task ends first,
so the tally of ``b6/a.exr`` came back in ``b6/b.jpg``'s result and the line named ``/abs/.../b6/a.exr``, the absolute
path only the worker had (``lenslab tonemap b6/ -o out/ --scheduler ...``, two files of three at once).

The worker's note is made here as a worker's task makes it (its file the absolute path the task was given); the value
checked is the path as the user typed it. No cluster is started: which task takes the tally is a matter of timing on
a real worker, so the crossing is set up, not waited for."""

from __future__ import annotations

import os


def test_a_workers_tally_names_the_file_as_given(tmp_path, monkeypatch, capsys):
    from lenslab.current_input import from_input
    from lenslab.jobs.runner import report_results
    from lenslab.tone import repairs

    monkeypatch.chdir(tmp_path)
    repairs.take()
    with from_input(os.path.abspath("b6/a.exr")):  # the task of a.exr on the worker
        repairs.add(506, -0.0064)
    note = repairs.take_note()  # handed back by the task of b.jpg, which ended first
    results = [("b6/a.exr", "out/a.jpg", None, []), ("b6/b.jpg", "out/b.jpg", None, [note])]
    report_results("lenslab tonemap", results, None)
    assert capsys.readouterr().err == ""  # (the tally goes into the command's one line, not a note of b.jpg)
    line = repairs.take_summary()
    assert line is not None and line.endswith("set to 0 in b6/a.exr"), line
