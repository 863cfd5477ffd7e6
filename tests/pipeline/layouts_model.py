"""Layouts of the smoke profile's model checks (``thesis validate oncilla --only convergence``
and ``thesis validate puppy``), checked on the datasets the smoke pipeline wrote: the
convergence tables' settings, cases, per-case rule and report tables. Their rules and
follow-up stage are tested on data whose answer is known in ``tests/modelcheck``; a second,
in-process run of each table at smoke size would add nothing but its minutes."""

from __future__ import annotations

import numpy as np

from thesis.ch5 import recordings as R
from thesis.modelcheck import puppy_convergence as PC
from thesis.modelcheck import validation as V
from thesis.registry import resolve
from thesis.report import validation as RV

VERDICTS = {"converged", "not converged", "inconclusive"}


def convergence(ds, cfg):
    """The Oncilla's table: dt, dt/2, 2x sweeps on every case, decided per case, and V1-V6
    at each setting on the validation's starts."""
    v = cfg["physics"]["oncilla_validation"]
    starts = v["convergence_starts"]
    assert resolve("model/convergence") is V.convergence
    assert ds.sizes["case"] == len(V.cases(v)) and ds.attrs["starts"] == starts
    assert list(ds["refined"].values) == ["dt/2", "2x sweeps"]
    assert set(ds["verdict"].values) <= VERDICTS
    assert ds.attrs["verdict"] == V.verdict_attrs(ds["verdict"].values)["verdict"]
    # the fall rates are the runs' own: each case's rate is a multiple of 1 / starts
    np.testing.assert_allclose((starts * ds["fall_rate"].values) % 1, 0, atol=1e-9)
    t = RV.convergence_table({"model/convergence": ds})
    assert len(t.rows) == 3 and t.rows[0][4] == "(reference)"
    assert t.rows[1][6].split(" (")[0] in VERDICTS
    # the rule decides per case: each case's fall-rate change, at the Oncilla's 3 % speeds
    assert ds["case_fall_rate_change"].dims == ("refined", "case")
    assert ds["starts_to_decide"].dims == ("refined", "case")
    assert ds.attrs["speed_tolerance"] == v["convergence_speed_tolerance"]
    assert ds.attrs["case_fall_tolerance"] == 0.15
    # V1-V6 at every setting, on the validation's starts
    assert ds["target_passed"].dims == ("setting", "target")
    assert ds.attrs["target_starts"] == min(v["starts"], starts)
    assert list(ds["target"].values) == ["V1", "V2", "V3", "V4", "V5", "V6"]
    for row, s in zip(t.rows, ds["setting"].values):
        failed = [str(x) for x, p in zip(ds["target"].values,
                                         ds["target_passed"].sel(setting=s).values) if not p]
        assert row[-1] == (", ".join(failed) or "none")
    assert f"{starts} perturbed starts" in t.note
    cases = RV.convergence_cases_table({"model/convergence": ds})
    assert cases.rows[0][0] == "tab3_1a"
    assert ds["stance_cable_taut"].dims == ("setting", "case", "leg")
    assert cases.rows[0][-1].startswith("knee stop ") and "cable taut" in cases.rows[0][-1]


def puppy_convergence(ds, cfg):
    """The Puppy II's table: the three settings on every non-empty Tab. 5.1 cell, each with
    the configured replicate trials, and the report's table with a row per cell."""
    assert resolve("model/puppy_convergence") is PC.convergence
    assert list(ds["setting"].values) == [s[0] for s in V.SETTINGS]
    cells = {(g, t, f) for (g, t), counts in R.TAB5_1.items()
             for f, n in zip(R.FREQUENCIES, counts) if n}
    assert {(str(g), str(t), float(f)) for g, t, f in zip(
        ds["case_gait"].values, ds["case_terrain"].values, ds["case_frequency"].values)} \
        == cells and ds.sizes["case"] == len(cells)
    # every case ran exactly trials_per_cell replicate trials (Tab. 5.1's 1-13 lifted)
    k = cfg["physics"]["puppy_convergence"]["trials_per_cell"]
    assert ds.attrs["trials_per_cell"] == k
    np.testing.assert_allclose((k * ds["fall_rate"].values) % 1, 0, atol=1e-9)
    m = cfg["ch5"]["model"]
    np.testing.assert_allclose(ds["dt"].values, [m["dt"], m["dt"] / 2, m["dt"]])
    assert ds["solver_iterations"].values.tolist() == [m["solver_iterations"]] * 2 \
        + [2 * m["solver_iterations"]]
    for name in ("case_speed", "case_speed_se", "fall_rate", "touch_std", "speed_change",
                 "speed_change_upper", "max_speed_change", "fall_rate_change", "verdict",
                 "touch_change"):
        assert name in ds and "units" in ds[name].attrs, name
    assert set(ds["verdict"].values) <= VERDICTS and ds.attrs["verdict"] in VERDICTS
    assert ds.attrs["speed_tolerance"] == cfg["physics"]["puppy_convergence"]["speed_tolerance"]
    t = RV.puppy_convergence_table({"model/puppy_convergence": ds})
    assert len(t.rows) == len(cells) and "converged" in t.note
    assert RV.puppy_convergence_table({}).rows == [[RV.NOT_RUN]]


CHECKS = {"model/convergence": convergence, "model/puppy_convergence": puppy_convergence}
