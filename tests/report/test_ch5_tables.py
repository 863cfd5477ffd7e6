"""Chapter 5's report tables show each accuracy's baselines (the test set's majority-class
share and chance) beside it, on the synthetic datasets of the ch5 claim tests."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.report.chapters import ch5
from thesis.report.model import NOT_RUN

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


def test_fig5_3_note_names_its_baselines(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    ds = fig5_3()
    conf = np.ones((ds.sizes["seed"], 2, 5, 5), int)
    ds["confusion"] = (("seed", "test", "true", "predicted"), conf)
    (fig,) = ch5.figures({"ch5/fig5_3": ds}, tmp_path)
    assert "majority-class share, frequency test 49.9" in fig.note
    assert "; chance 20 (" in fig.note
