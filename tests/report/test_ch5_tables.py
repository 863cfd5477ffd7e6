"""Chapter 5's report tables show each accuracy's baselines (the test set's majority-class
share and chance) beside it, on the synthetic datasets of the ch5 claim tests."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.report.chapters import ch5
from thesis.report.model import NOT_RUN

from ..claims import test_ch5
from ..claims.test_ch5 import fig5_3, table5_3, table5_4, table5_5, table5_6


def _mean(cell: str) -> float:
    """The mean of a ``mean ± sd (n=k)`` cell."""
    return float(cell.split()[0])


def _results():
    return {"ch5/table5_3": table5_3(), "ch5/table5_4": table5_4(),
            "ch5/table5_5": table5_5(), "ch5/table5_6": table5_6()}


def test_every_accuracy_table_has_baseline_columns():
    tables = {t.id: t for t in ch5.tables(_results())}
    for tid in ("table5_3", "table5_4", "table5_5"):
        t = tables[tid]
        assert t.columns[-2:] == ch5.BASELINE_COLUMNS, tid
        assert all(len(r) == len(t.columns) for r in t.rows), tid
        assert _mean(t.rows[0][-2]) == pytest.approx(30, abs=0.5), (tid, t.rows[0])
        assert t.rows[0][-1] == "20"
        assert "majority-class share" in t.note
    t6 = tables["table5_6"]
    assert t6.columns[-2:] == ["majority share of the split", "chance"]
    train, test = t6.rows[0], t6.rows[-1]
    assert _mean(train[-2]) == pytest.approx(20, abs=0.5)
    assert _mean(test[-2]) == pytest.approx(35, abs=0.5)


def test_baselines_not_run_without_results():
    tables = {t.id: t for t in ch5.tables({})}
    assert tables["table5_3"].rows[0][-2:] == [NOT_RUN, NOT_RUN]
    assert tables["table5_4"].rows[0][-2:] == [NOT_RUN, NOT_RUN]


def test_fig5_3_note_names_its_baselines(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.setattr(test_ch5, "SEEDS", 3)  # the note's figures are those of 3 seeds
    ds = fig5_3()
    conf = np.ones((ds.sizes["seed"], 2, 5, 5), int)
    ds["confusion"] = (("seed", "test", "true", "predicted"), conf)
    (fig,) = ch5.figures({"ch5/fig5_3": ds}, tmp_path)
    assert "majority-class share, frequency test 49.9" in fig.note
    assert "; chance 20 (" in fig.note


def _separability(acc_best: float, seeds=(0, 1, 2)):
    """A synthetic ch5/separability dataset: one five-terrain cell and one two-terrain cell;
    RC scores ``acc_best`` in every cell, the other methods 10."""
    import xarray as xr

    methods = ["lr", "elm", "rc", "sfa2", "elm_sfa", "rc_sfa"]
    cells = ["bound_right 1.00 Hz", "bound_right 0.50 Hz"]
    acc = np.full((len(seeds), 2, 3, 6), 10.0)
    acc[..., 2] = acc_best
    ds = xr.Dataset(coords={"seed": list(seeds), "cell": cells,
                            "selection": ["minimal", "touch", "imu"], "method": methods,
                            "terrain": list(ch5.TERRAINS)})
    ds["accuracy"] = (("seed", "cell", "selection", "method"), acc)
    ds["trials"] = (("cell", "terrain"), np.array([[2, 13, 9, 3, 5], [5, 2, 0, 0, 0]]))
    ds["majority_share"] = ("cell", [40.0, 70.0])
    ds["chance"] = ("cell", [20.0, 50.0])
    ds.attrs.update(nodes=100, hyper_parameters="{}")
    return ds


def test_separability_table_has_baselines_and_says_what_the_numbers_show():
    t = ch5.separability_table({"ch5/separability": _separability(80.0)})
    assert t.columns[-2:] == ["majority share", "chance"]
    assert len(t.rows) == 6 and all(len(r) == len(t.columns) for r in t.rows)
    assert t.rows[0][:3] == ["bound_right 1.00 Hz", "minimal", "F2 S13 L9 C3 R5"]
    assert t.rows[0][-2:] == ["40", "20"] and t.rows[-1][-2:] == ["70", "50"]
    assert _mean(t.rows[0][3 + 2]) == pytest.approx(80.0)  # the RC column
    assert "can be told apart" in t.note and "majority share 40" in t.note
    low = ch5.separability_table({"ch5/separability": _separability(35.0)})
    assert "cannot be told apart" in low.note
    assert ch5.separability_table({}).rows[0][0] == NOT_RUN


def _with_cells(ds, seen=70.0, unseen=30.0):
    """Add the generalisation map and fold-sharing variables of the experiments."""
    cells = np.stack([np.full(ds["accuracy"].isel(split=0).shape, seen),
                      np.full(ds["accuracy"].isel(split=0).shape, unseen)], -1)
    dims = [d for d in ds["accuracy"].dims if d != "split"] + ["cells"]
    ds = ds.assign_coords(cells=["seen", "unseen"])
    ds["accuracy_cells"] = (dims, cells)
    ds["seen_share"] = ("seed", np.full(ds.sizes["seed"], 20.0))
    ds["majority_share_cells"] = (("seed", "cells"), np.tile([50.0, 45.0], (ds.sizes["seed"],
                                                                             1)))
    ds["shared_tuning"] = (("seed", "tuning_fold"), np.zeros((ds.sizes["seed"], 3)))
    ds["shared_verification"] = (("seed", "fold"), np.zeros((ds.sizes["seed"], 2)))
    ds.attrs.update(selection_mode="trials", selection_levels='{"0": {"C": "stages"}}')
    return ds


def test_generalisation_map_and_protocols_side_by_side():
    res = {"ch5/table5_3": _with_cells(table5_3()),
           "ch5/table5_3_blocks": _with_cells(table5_3(), seen=90.0)}
    gen = ch5.generalisation_table(res)
    rows = [r for r in gen.rows if r[0] == "Tab. 5.3"]
    assert len(rows) == 16 and rows[0][1] == "useful LR"
    assert _mean(rows[0][2]) == pytest.approx(70.0) and _mean(rows[0][3]) == pytest.approx(30.0)
    assert _mean(rows[0][5]) == pytest.approx(50.0) and _mean(rows[0][6]) == pytest.approx(45.0)
    assert [r for r in gen.rows if r[0] == "Tab. 5.5"][0][1] == NOT_RUN  # not run
    prot = ch5.protocols_table(res)
    assert prot.columns[1].startswith("primary (trials)")
    assert all(len(r) == len(prot.columns) for r in prot.rows)
    assert prot.rows[0][11:] == [NOT_RUN] * 5  # the parts variant did not run
    assert prot.rows[0][5] == "0 / 0" and "C stages" in prot.note
