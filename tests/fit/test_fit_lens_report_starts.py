"""``fit lens`` runs a local search from the source's own values and another from the model's defaults; the
report's nlopt line says which is which, so a second, worse best (a local minimum) reads as that and not as
the fit's figure. The kept one is the one the fitted spec and residual come from."""

from __future__ import annotations

from lenslab.fit import fit_lens


def test_each_local_search_names_its_start():
    fit = fit_lens("distortion:k1=-0.05,fov=60", "brown", size=(64, 64), global_start=None, report_grid=17)
    line = next(x for x in fit.report() if x.startswith("nlopt:"))
    stages = line[len("nlopt:"):].strip().split("; ")
    assert len(stages) == 2, line
    assert "from the source's values" in stages[0] and "from the model's defaults" in stages[1], line
    # the kept search's best is the smallest of the two (what the fitted spec comes from)
    bests = [float(s.split("best ")[1].split()[0]) for s in stages]
    assert fit.optimizer.value == min(bests) or abs(fit.optimizer.value - min(bests)) <= 1e-6 * min(bests)
