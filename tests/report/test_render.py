"""The report renders thesis-vs-reproduced tables, figures, claims and provenance, and
shows "not run" for what is missing -- on datasets built inside the test."""

from __future__ import annotations

import json
import sys
import types
from datetime import datetime, timezone

import numpy as np
import pytest
import xarray as xr

from thesis import store
from thesis.report import render
from thesis.report.model import NOT_RUN, Figure, Table


@pytest.fixture
def fake_chapter(monkeypatch):
    """A chapter module for ch3 that reads its numbers from the results it is given."""
    mod = types.ModuleType("thesis.report.chapters.ch3")

    def tables(results):
        ds = results.get("ch3/fig3_4")
        cell = f"{float(ds['speed'].mean()):.3f}" if ds is not None else NOT_RUN
        return [Table(id="fig3_4", title="Speed", thesis_ref="Fig. 3.4",
                      columns=["gait", "reproduced"], rows=[["sine", cell]])]

    def figures(results, outdir):
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots()
        ax.plot(results["ch3/fig3_4"]["speed"].values)
        path = outdir / "fig3_4.png"
        fig.savefig(path)
        plt.close(fig)
        return [Figure(id="fig3_4", title="Speed against frequency", thesis_ref="Fig. 3.4",
                       path=path)]

    mod.tables, mod.figures = tables, figures
    monkeypatch.setitem(sys.modules, "thesis.report.chapters.ch3", mod)
    return mod


def _write_result(root):
    ds = xr.Dataset({"speed": xr.DataArray(np.array([0.25, 0.35]), dims="seed",
                                           attrs={"units": "m s-1", "long_name": "speed"})},
                    coords={"seed": [0, 1]}, attrs={"thesis_ref": "Fig. 3.4", "seeds": [0, 1]})
    store.write_dataset(ds, root / "smoke" / "ch3" / "fig3_4.nc", profile="smoke",
                        experiment="ch3/fig3_4", config_slice={}, wall_seconds=2.0,
                        started=datetime.now(timezone.utc))


_DEVIATION = {"id": "ch3.pso_budget", "kind": "deviation", "thesis": "10 x 10 swarm",
              "ours": "a tiny swarm", "why": "smoke budget", "results": ["ch3/fig3_4"],
              "config": {"ch3.pso.half_ellipse.particles": 4}, "in_effect": True,
              "paper": [{"key": "sec3.3.1.2/pso_particles", "value": 10.0, "unit": "1"}]}
_CHOICE = {"id": "ch3.sweep_protocol", "kind": "choice", "thesis": "silent",
           "ours": "a grid", "why": "silent", "results": ["ch3/fig3_4"], "config": {},
           "in_effect": True, "paper": []}


def _write_claims(root):
    claims = [{"id": "ch3.half_ellipse_fastest", "chapter": 3, "section": "§3",
               "quote": "fastest gaits", "summary": "half ellipse beats both",
               "paper": [{"key": "fig3_4/x", "value": 0.3, "unit": "m/s"}],
               "measured": {"speed": 0.3}, "statistic": "bootstrap", "status": "reproduced",
               "reading": "reproduced under a declared deviation", "detail": "ok",
               "departures": [_DEVIATION, _CHOICE]},
              {"id": "ch5.terrain", "chapter": 5, "section": "§5", "quote": "classifies",
               "summary": "", "paper": [], "measured": {}, "statistic": "",
               "status": "not_run", "reading": "not run", "detail": "ch5/table5_3 missing",
               "departures": []},
              {"id": "ch8.ch3_x", "chapter": 8, "section": "§8.1", "quote": "conclusion",
               "summary": "", "paper": [], "measured": {}, "statistic": "",
               "status": "inconclusive", "reading": "inconclusive as stated",
               "detail": "only 1 seed", "departures": []}]
    (root / "smoke").mkdir(parents=True, exist_ok=True)
    (root / "smoke" / "claims.json").write_text(json.dumps({"claims": claims}))


def test_report_shows_values_figures_claims_and_not_run(tmp_path, fake_chapter):
    results, out = tmp_path / "results", tmp_path / "reports"
    _write_result(results)
    _write_claims(results)
    figs = render.render_figures("ch3", "smoke", out, results_root=results)
    assert [f.id for f in figs] == ["fig3_4"]
    manifest = json.loads((out / "figures" / "ch3" / "manifest.json").read_text())
    assert manifest[0]["path"] == "fig3_4.png"
    index = render.render_report("smoke", out, results_root=results)
    page = index.read_text()
    assert "0.300" in page                      # mean of the stored speeds
    assert "data:image/png;base64," in page     # figure inlined
    assert "ch3.half_ellipse_fastest" in page and "reproduced" in page
    assert "ch5/table5_3 missing" in page
    assert page.count(NOT_RUN) >= 3             # chapters without modules or results
    assert "Provenance" in page and "ch3/fig3_4" in page
    assert (out / "tables" / "ch3_fig3_4.html").exists()
    assert (out / "tables" / "claims.html").exists()
    summary = (out / "summary.md").read_text()
    assert "| sine | 0.300 |" in summary
    assert "reproduced under a declared deviation 1" in summary
    # the verdict's departures beside it, in the page and in summary.md
    assert "fastest gaits" in page and "ch3.pso_budget" in page and "ch3.sweep_protocol" in page
    assert "ch3.pso.half_ellipse.particles = 4" in page and "sec3.3.1.2/pso_particles" in page
    bullet = summary.split("`ch3.half_ellipse_fastest`")[1].split("\n- ")[0]
    assert "deviation ch3.pso_budget" in bullet and "`ch3.sweep_protocol`" in bullet
    assert "§8.1" in summary and "ch8.ch3_x" in summary


def test_missing_results_show_not_run_never_numbers(tmp_path, fake_chapter):
    results, out = tmp_path / "results", tmp_path / "reports"
    figs = render.render_figures("ch3", "smoke", out, results_root=results)
    assert figs == []
    page = render.render_report("smoke", out, results_root=results).read_text()
    assert "| sine | not run |" in (out / "summary.md").read_text()
    assert "data:image/png" not in page
