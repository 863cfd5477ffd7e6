"""Report table of the held-out-gait test of the Puppy II's terrains
(``results/<profile>/model/puppy_heldout.nc``, ``thesis bench puppy-heldout``,
:mod:`thesis.modelcheck.puppy_heldout`): per held-out gait and pooled, the reservoir's
accuracy against the held-out set's majority share with the t interval of the
difference and its verdict, the linear discriminant beside it; the within-cell test's
verdict in the note.

Every number is read from the dataset; without one the table says "not run".
"""

from __future__ import annotations

import numpy as np

from thesis.report.model import NOT_RUN, Table

KEY = "model/puppy_heldout"
COLUMNS = ["held out", "test steps", "reservoir [%] (mean of seeds)", "majority share [%]",
           "difference [points] (95 % t interval)", "rule", "linear discriminant [%]"]


def _diff(mean, low, high) -> str:
    return f"{float(mean):.1f} ({float(low):.1f} to {float(high):.1f})"


def table(results: dict) -> Table:
    """One row per held-out gait (reported) and the pooled row (deciding)."""
    ds = results.get(KEY)
    title = "Puppy II terrains across gaits: one gait held out, reservoir on touch"
    ref = "§5.3-5.4"
    if ds is None:
        return Table(id="puppy_heldout", title=title, thesis_ref=ref, columns=COLUMNS,
                     rows=[[NOT_RUN] * len(COLUMNS)])
    rows = []
    for g in ds["heldout"].values:
        d = ds.sel(heldout=g)
        rows.append([str(g), str(int(d["test_steps"])),
                     f"{float(d['accuracy'].mean()):.1f}",
                     f"{float(d['majority_share']):.1f}",
                     _diff(d["difference_mean"], d["difference_low"], d["difference_high"]),
                     "pass" if bool(d["passed"]) else "fail",
                     f"{float(d['lda_accuracy']):.1f}"])
    rows.append(["pooled (decides)", str(int(ds["test_steps"].sum())),
                 f"{float(ds['pooled_accuracy'].mean()):.1f}",
                 f"{float(ds['pooled_majority_share']):.1f}",
                 _diff(ds["pooled_difference_mean"], ds["pooled_difference_low"],
                       ds["pooled_difference_high"]),
                 "PASS" if bool(ds["pooled_passed"]) else "FAIL",
                 f"{float(ds['pooled_lda_accuracy']):.1f}"])
    cells = ds["cell_accuracy"].mean("seed").values
    note = (f"Terrains {ds.attrs['terrains']}, sensor group {ds.attrs['selection']}, "
            f"reservoir of {ds.attrs['nodes']} nodes at the CMA-ES start point "
            f"{ds.attrs['params']}, {ds.sizes['seed']} draws; rule: mean difference >= "
            f"the bench's min_difference and lower bound > its min_lower_bound (module "
            f"thesis.modelcheck.puppy_heldout). {ds.attrs['test_a']}. {ds.attrs['test_b']}; "
            f"per cell {np.nanmin(cells):.1f}-{np.nanmax(cells):.1f} % over "
            f"{ds.sizes['cell']} cells (first half of each trial trains, second half tests).")
    return Table(id="puppy_heldout", title=title, thesis_ref=ref, columns=COLUMNS, rows=rows,
                 note=note)


def tables(results: dict) -> list[Table]:
    """The held-out-gait table."""
    return [table(results)]
