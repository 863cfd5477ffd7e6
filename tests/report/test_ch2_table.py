"""Tab. 2.2 in the report when a profile runs only part of the d grid (default: d = 2)."""

import numpy as np
import xarray as xr

from thesis.report.chapters import ch2
from thesis.report.model import NOT_RUN


def _table(ds_values):
    err = np.full((2, len(ds_values), 4, 3), 0.25)
    err[1] = 0.5  # rnn_spn
    ds = xr.Dataset(
        {"test_error": (("model", "d", "transform", "seed"), err, {"units": "1"})},
        coords={"model": ["ffn_spn", "rnn_spn"], "d": ds_values,
                "transform": list(ch2.TRANSFORMS), "seed": [0, 1, 2]},
    )
    return ch2.tables({"ch2/table2_2": ds})[0]


def test_rows_outside_the_run_grid_say_not_run_and_the_note_names_the_grid():
    t = _table([2])
    rows = {r[0]: r for r in t.rows}
    reproduced = [2 * i + 2 for i in range(len(ch2.TRANSFORMS))]  # columns after the thesis'
    assert all(rows["FFN-SPN d=1"][c] == NOT_RUN for c in reproduced)
    assert all(rows["RNN-SPN d=3"][c] == NOT_RUN for c in reproduced)
    assert rows["FFN-SPN d=2"][2].startswith("25")  # percent, mean over 3 seeds
    assert rows["RNN-SPN d=2"][2].startswith("50")
    assert "d run: [2]" in t.note
    assert "d run: [1, 2, 3]" in _table([1, 2, 3]).note


def test_cells_carry_the_t_interval_the_claims_decide_on():
    from scipy import stats as sps

    err = np.full((2, 1, 4, 3), 0.25)
    err[0, 0, 0] = [0.19, 0.14, 0.27]  # ffn_spn, d=1, bilinear: three seeds
    ds = xr.Dataset(
        {"test_error": (("model", "d", "transform", "seed"), err, {"units": "1"})},
        coords={"model": ["ffn_spn", "rnn_spn"], "d": [1],
                "transform": list(ch2.TRANSFORMS), "seed": [0, 1, 2]},
    )
    t = ch2.tables({"ch2/table2_2": ds})[0]
    cell = {r[0]: r for r in t.rows}["FFN-SPN d=1"][2]
    v = np.array([19.0, 14.0, 27.0])
    half = sps.t.ppf(0.975, 2) * v.std(ddof=1) / np.sqrt(3)
    assert cell == f"20 [{v.mean() - half:.3g}, {v.mean() + half:.3g}] (n=3)"
    assert "95 % Student t interval" in t.note
    assert {r[0]: r for r in t.rows}["FFN-SPN d=1"][4] == "25 [25, 25] (n=3)"  # equal seeds
