"""Layouts of the smoke profile's model checks (``thesis validate oncilla`` and ``thesis
validate puppy``), checked on the datasets the smoke pipeline wrote: the Oncilla's
validation (every quantity, every target decided) and calibration (grid, brackets,
refinements, fit), the convergence tables' settings, cases, per-case rule and report
tables. Their rules and follow-up stage are tested on data whose answer is known in
``tests/modelcheck``; a second, in-process run of each check at smoke size would add
nothing but its minutes."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.ch5 import recordings as R
from thesis.modelcheck import calibration as CAL
from thesis.modelcheck import pebbles as PB
from thesis.modelcheck import puppy_convergence as PC
from thesis.modelcheck import targets as TG
from thesis.modelcheck import validation as V
from thesis.registry import VALIDATIONS, resolve
from thesis.report import validation as RV

VERDICTS = {"converged", "not converged", "inconclusive"}


def validation(ds, cfg):
    """V1-V6's instrument: every quantity with units, every published flat gait at the
    configured frequencies and starts, every target decided (whatever its outcome)."""
    v = cfg["physics"]["oncilla_validation"]
    assert resolve("model/validation") is V.validation
    assert VALIDATIONS["oncilla"] == ("model/validation", "model/convergence",
                                      "model/calibration", "model/pebbles")
    assert ds.sizes["case"] == len(V.cases(v)) and ds.sizes["start"] == v["starts"]
    for name in ("speed", "fallen", "roll_max", "pitch_max", "stance_compression",
                 "scapula_max_deviation", "reach_outside", "target_passed", "target_text",
                 "V1_speed_1p5Hz", "V3_falls", "stance_knee_stop", "stance_cable_taut"):
        assert name in ds and "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    up = ds["fallen"].values == 0
    shares = ds["stance_cable_taut"].values[up]
    assert ds["stance_knee_stop"].dims == ("case", "start", "leg")
    # a leg without stance in the window has no share (NaN); the others lie in [0, 1]
    assert np.isfinite(shares).any()
    assert np.all((shares[np.isfinite(shares)] >= 0) & (shares[np.isfinite(shares)] <= 1))
    assert list(ds["target"].values) == list(TG.TARGETS)
    assert set(np.unique(ds["target_passed"].values)) <= {0, 1}
    assert int(ds["V3_falls"]) == int(ds["fallen"].sum())
    # the text renders the decided numbers and is not regressed itself
    assert ds["target_text"].attrs["renders"]
    assert all(str(t) for t in ds["target_text"].values)
    assert np.all(ds["scapula_max_deviation"].values[up] >= 0)
    # an upright trot's legs carry the robot: stance length within 3 cm of the command
    assert np.all(np.abs(ds["stance_compression"].values[up]) < 0.03)


def calibration(ds, cfg):
    """The knee spring's calibration against V1: the grid, each bracket refined within
    itself, the fit as the run nearest the target, the configured spring beside it."""
    c, model = cfg["physics"]["oncilla_calibration"], cfg["ch4"]["model"]
    assert resolve("model/calibration") is CAL.calibration
    assert list(ds["knee_spring"].values) == list(c["grid"])
    assert ds.sizes["start"] == c["starts"]
    for name in ("grid_speed", "grid_fallen", "grid_gait_speed", "grid_compression",
                 "refinement_knee_spring", "refinement_bracket", "refinement_speed",
                 "refinement_fallen", "refinement_gait_speed", "bracket_stiff",
                 "bracket_soft", "grid_starts_agree", "refinement_starts_agree",
                 "agreement_width", "fit_starts_agree", "target_speed", "target_low", "target_high",
                 "fitted_knee_spring", "fit_inside_grid", "fit_holds", "residual_speed",
                 "residual", "configured_knee_spring", "configured_matches_fit"):
        assert name in ds and "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    target = float(ds["target_speed"])
    found = CAL.brackets(ds["knee_spring"].values, ds["grid_gait_speed"].values, target)
    assert [(b[0], b[1]) for b in found] == list(zip(ds["bracket_stiff"].values,
                                                      ds["bracket_soft"].values))
    # every refinement run lies inside its bracket, at most `refinements` per bracket
    for i, (hi, lo, _, _) in enumerate(found):
        ks = ds["refinement_knee_spring"].values[ds["refinement_bracket"].values == i]
        assert len(ks) <= c["refinements"] and all(lo <= k <= hi for k in ks)
    # the fit is the run (grid or refinement) nearest the target, and its own speed
    ks = np.concatenate([ds["knee_spring"].values, ds["refinement_knee_spring"].values])
    vs = np.concatenate([ds["grid_gait_speed"].values, ds["refinement_gait_speed"].values])
    ag = np.concatenate([ds["grid_starts_agree"].values, ds["refinement_starts_agree"].values])
    i = CAL.choose(vs, target, ag.astype(bool))
    assert int(ds["fit_starts_agree"]) == int(ag[i])
    assert float(ds["fitted_knee_spring"]) == pytest.approx(ks[i])
    assert float(ds["residual_speed"]) == pytest.approx(vs[i])
    assert float(ds["residual"]) == pytest.approx(abs(vs[i] - target))
    assert int(ds["fit_holds"]) == int(bool(ag[i]) and 0.27 <= vs[i] <= 0.30)
    assert float(ds["configured_knee_spring"]) == model["knee_spring"]
    assert int(ds["configured_matches_fit"]) == int(
        abs(model["knee_spring"] - ks[i]) <= CAL.MATCH_TOLERANCE * ks[i])
    # a softer knee spring compresses the stance leg more (§3.3.1.2's mechanism)
    comp = ds["grid_compression"].values[:, 0]
    assert comp[np.argmin(ds["knee_spring"].values)] > comp[np.argmax(ds["knee_spring"].values)]
    assert ds.attrs["solver_iterations"] == model["solver_iterations"]
    assert ds.attrs["sweep_order"] == model["sweep_order"]
    # the report's table: the grid, each refinement, the fit, and whether the chapters run it
    t = RV.calibration_table({"model/calibration": ds})
    roles = [r[-1] for r in t.rows]
    assert roles[:len(c["grid"])] == ["grid"] * len(c["grid"]) and roles[-1].startswith("fit")
    assert sum(r.startswith("refinement of") for r in roles) == ds.sizes["refinement"]
    assert "residual" in t.note and "calibration target" in t.note
    assert "starts agree" in t.note and "spread by at most 0.03 m/s" in t.note
    assert ("it holds" in t.note) == bool(int(ds["fit_holds"]))
    assert ("the fit." in t.note) == bool(int(ds["configured_matches_fit"]))
    assert RV.calibration_table({}).rows == [[RV.NOT_RUN] * 5]


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


def pebbles(ds, cfg):
    """V7's runs: Tab. 4.4's three pebble optima on both floors from the configured starts,
    the target decided from the pebble runs (whatever its outcome)."""
    assert resolve("model/pebbles") is PB.pebbles
    n = cfg["physics"]["oncilla_pebbles"]["starts"]
    assert list(ds["floor"].values) == list(PB.FLOORS)
    assert list(ds["gait"].values) == [g.name for g in TG.pebble_gaits()]
    assert ds.sizes["start"] == n and list(ds["target"].values) == [TG.PEBBLE_TARGET]
    for name in ("speed", "fallen", "score", "taut", "case_speed", "case_falls",
                 "published_speed", "speed_low", "speed_high", "target_passed",
                 "target_text"):
        assert name in ds and "units" in ds[name].attrs, name
    falls = ds["fallen"].sel(floor="pebbly").sum("start").values
    assert list(falls) == list(ds["case_falls"].sel(floor="pebbly").values)
    lo, hi = ds["speed_low"].values, ds["speed_high"].values
    assert np.allclose(lo, 0.75 * ds["published_speed"].values) and np.all(hi > lo)
    assert set(ds["target_passed"].values) <= {0, 1}
    # the pebble runs start along the strip, after its margin
    assert np.all(ds["start_x"].values >= cfg["ch4"]["pebbles"]["start_margin"])
    t = RV.pebbles_table({"model/pebbles": ds})
    assert len(t.rows) == 3 and t.note.startswith("V7 ")
    assert RV.pebbles_table({}).rows == [[RV.NOT_RUN] * 4]


CHECKS = {"model/validation": validation, "model/calibration": calibration,
          "model/convergence": convergence, "model/puppy_convergence": puppy_convergence,
          "model/pebbles": pebbles}
