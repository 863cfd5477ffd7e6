"""The measurements behind chapter 2's configured sizes, as report tables.

Two datasets that the pipeline makes outside ``make all`` (``snakemake ch2_pilot``,
workflow/rules/ch2.smk) and that the ch2 sizes of ``config/<profile>.yaml`` cite:

- ``ch2/width_pilot`` (:func:`thesis.ch2.width_pilot.width_pilot`): per-digit error of
  one Tab. 2.2 cell against the CPU time of its run, per width and run length;
- ``ch2/train_step`` (:func:`thesis.ch2.train_bench.train_step`): the time and XLA's
  floating-point operation count of one training step (forward, backward and update)
  per model, transform and d, and where the step's time goes.

Every number shown is read from those datasets; an absent one gives a table that says
so and names the command that makes it.
"""

from __future__ import annotations

import numpy as np

from thesis.report.model import NOT_RUN, Table

__all__ = ["MAKE", "tables", "train_step_table", "width_pilot_table"]

#: The command that makes both datasets (the profile's own is in the report's status).
MAKE = "snakemake ch2_pilot --config profile=<profile> --cores 2"

_SPLITS = {"test": "test (%)", "train_pool": "train pool (%)", "train_seen": "seen (%)"}


def _num(v: float, fmt: str = ".3g") -> str:
    """A number as text, NOT_RUN where it is not finite."""
    v = float(v)
    return format(v, fmt) if np.isfinite(v) else NOT_RUN


def _absent(key: str, columns: list[str]) -> list[list[str]]:
    """The one row of a table whose dataset is absent."""
    return [[f"{NOT_RUN}: `{MAKE}` makes results/<profile>/{key}.nc"]
            + [NOT_RUN] * (len(columns) - 1)]


def width_pilot_table(results: dict) -> Table:
    """``ch2/width_pilot``: one row per width and run length, with the per-digit error [%]
    on each evaluation split, the run's CPU and wall time [s], the CPU time per update
    [ms] of the width (from its shortest and longest runs) and the mean fraction of the
    sampling grid left on the canvas."""
    ds = results.get("ch2/width_pilot")
    columns = ["width (loc / cls, filters/dense)", "updates", "parameters",
               *_SPLITS.values(), "CPU [s]", "wall [s]", "CPU per update [ms]",
               "grid on canvas", "failed"]
    if ds is None:
        return Table(id="width_pilot", title="Width pilot: error against CPU time",
                     thesis_ref="§2.5, Tab. 2.1", columns=columns,
                     rows=_absent("ch2/width_pilot", columns),
                     note="The ch2 widths of config/<profile>.yaml cite this table.")
    rows = []
    for w in ds["width"].values:
        for s in ds["steps"].values:
            at = dict(width=w, steps=s)
            err = [_num(100 * ds["error"].sel(**at, split=k), ".1f")
                   for k in _SPLITS if k in ds["split"].values]
            rows.append([str(w), str(int(s)), _num(ds["n_params"].sel(width=w), ".0f"), *err,
                         _num(ds["cpu_seconds"].sel(**at)),
                         _num(ds["wall_seconds"].sel(**at)),
                         _num(1e3 * ds["step_cpu_seconds"].sel(width=w)),
                         _num(ds["inside_fraction"].sel(**at), ".2f"),
                         "yes" if int(ds["failed"].sel(**at)) else "no"])
    a = ds.attrs
    seeds = [int(s) for s in np.atleast_1d(a.get("seeds", []))]
    note = (f"{a.get('model')} {a.get('transform')} d = {a.get('d')}, seed {seeds}; "
            f"{a.get('n_train')} training sequences, {a.get('n_eval')} per evaluation "
            "split (test: held-out canvases of test-pool digits; train pool: held-out canvases of train-pool digits; seen: "
            f"the first training canvases); batch {a.get('batch_size')}; digits: "
            f"{a.get('digit_source')}; one run per length with the profile's schedule "
            "fitted to it. CPU: the process's CPU time (all threads), compilation excluded, "
            "evaluations included; per update: the difference of a width's longest and "
            f"shortest runs. Backend {a.get('backend')} ({a.get('device')}), host "
            f"{a.get('host', '?')}.")
    return Table(id="width_pilot", title="Width pilot: error against CPU time",
                 thesis_ref=str(a.get("thesis_ref", "§2.5, Tab. 2.1")), columns=columns,
                 rows=rows, note=note)


#: The parts of a training step (:data:`thesis.ch2.train_bench.PARTS`) shown, in order.
_PARTS = ("step", "forward", "localisation", "transform", "classifier", "update")


def train_step_table(results: dict) -> Table:
    """``ch2/train_step``: one row per model, transform and d, with the median wall time
    [ms] of the whole step and of each separately compiled part (— where the cell has no
    such part), the step's CPU time [ms], its work [GFLOP] and the parameters."""
    ds = results.get("ch2/train_step")
    columns = ["cell", *(f"{p} [ms]" for p in _PARTS), "step CPU [ms]", "step [GFLOP]",
               "parameters"]
    if ds is None:
        return Table(id="train_step", title="Cost of one training step per cell",
                     thesis_ref="§2.5, Tab. 2.1", columns=columns,
                     rows=_absent("ch2/train_step", columns),
                     note="The ch2 run lengths of config/<profile>.yaml cite this table.")
    rows = []
    parts = [p for p in _PARTS if p in ds["part"].values]
    for m in ds["model"].values:
        for t in ds["transform"].values:
            for d in ds["d"].values:
                at = dict(model=m, transform=t, d=d)
                wall = [float(ds["seconds"].sel(**at, part=p)) for p in parts]
                rows.append([f"{m} {t} d={int(d)}",
                             *("—" if w == 0 else _num(1e3 * w) for w in wall),
                             _num(1e3 * ds["cpu_seconds"].sel(**at, part="step")),
                             _num(1e-9 * ds["step_flops"].sel(**at)),
                             _num(ds["n_params"].sel(**at), ".0f")])
    a = ds.attrs
    note = (f"Batch {a.get('batch')}, median of {a.get('repeats')} timed calls after "
            "compilation; the parts are compiled apart, so they need not sum to the step. "
            f"Widths {a.get('widths')}. Backend {a.get('backend')} ({a.get('device')}), host "
            f"{a.get('host', '?')}. Work: XLA's count of the lowered step's operations, the "
            "same on every device.")
    return Table(id="train_step", title="Cost of one training step per cell",
                 thesis_ref=str(a.get("thesis_ref", "§2.5, Tab. 2.1")), columns=columns,
                 rows=rows, note=note)


def tables(results: dict) -> list[Table]:
    """The width pilot's and the training-step bench's tables (absent: how to make them)."""
    return [width_pilot_table(results), train_step_table(results)]
