"""The committed calibration of the Oncilla's knee spring (thesis.modelcheck.calibration,
``thesis validate oncilla --only calibration``): the procedure's fit on known numbers, the
procedure end to end on a tiny grid, and the marks and tables it feeds. No test asserts the
fitted value of the current model (that is what the procedure reports)."""

from __future__ import annotations

import logging
import math
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from thesis import registry
from thesis.claims import CLAIMS, model_validity as MV
from thesis.config import load_config
from thesis.modelcheck import calibration as CAL
from thesis.modelcheck import targets as TG
from thesis.report import validation as RV
from thesis.report import verdicts as VD


def test_target_is_the_midpoint_of_the_thesis_s_two_speeds_of_tab3_1a():
    assert CAL.target_speed() == pytest.approx(0.5 * (0.27 + 0.30))
    case = CAL.v1_case()
    assert case["gait"] == "tab3_1a" and case["frequency"] == TG.V1_FREQUENCY == 1.5


def test_fit_interpolates_linearly_in_log_k_between_the_bracketing_grid_points():
    grid = [10.0, 5.0, 3.0, 2.0, 1.5, 1.0]
    speeds = [0.449, 0.336, 0.358, 0.2897, 0.242, 0.011]
    fit = CAL.fit_log_linear(grid, speeds, 0.285)
    t = (0.285 - 0.2897) / (0.242 - 0.2897)
    want = math.exp(math.log(2.0) + t * (math.log(1.5) - math.log(2.0)))
    assert fit["inside"] and fit["bracket"] == (2.0, 1.5)
    assert fit["value"] == pytest.approx(want) and 1.5 < fit["value"] < 2.0
    # grid order does not matter; an exact grid speed gives that grid point
    assert CAL.fit_log_linear(grid[::-1], speeds[::-1], 0.285)["value"] == pytest.approx(want)
    assert CAL.fit_log_linear(grid, speeds, 0.2897)["value"] == pytest.approx(2.0)


def test_fit_takes_the_first_bracket_from_the_stiffest_spring_and_skips_fallen_points():
    # speed rises again at 3 (non-monotone): 0.34 is bracketed by 10-5 and by 5-3
    fit = CAL.fit_log_linear([10.0, 5.0, 3.0, 2.0], [0.45, 0.32, 0.36, 0.29], 0.34)
    assert fit["bracket"] == (10.0, 5.0)
    # a fallen grid point (NaN) brackets nothing
    fit = CAL.fit_log_linear([10.0, 5.0, 2.0], [0.45, np.nan, 0.20], 0.30)
    assert not fit["inside"] and fit["value"] == 2.0


def test_fit_outside_the_grid_is_the_nearest_point_and_says_so():
    fit = CAL.fit_log_linear([10.0, 5.0], [0.45, 0.40], 0.285)
    assert not fit["inside"] and fit["value"] == 5.0 and fit["bracket"] == (5.0, 5.0)
    with pytest.raises(ValueError, match="every run fell"):
        CAL.fit_log_linear([10.0, 5.0], [np.nan, np.nan], 0.285)


@pytest.fixture(scope="module")
def tiny():
    config = load_config("smoke", overrides={"physics": {
        "oncilla_calibration": dict(grid=[10.0, 2.0], starts=1, seconds=0.3),
        "oncilla_validation": dict(batch=4)}})
    ctx = SimpleNamespace(full_config=config, root_seed=int(config["root_seed"]),
                          key="model/calibration", log=logging.getLogger("test"))
    return CAL.calibration(ctx), config


def test_calibration_runs_the_grid_fits_and_measures_the_residual(tiny):
    ds, config = tiny
    assert registry.resolve("model/calibration") is CAL.calibration
    assert list(ds["knee_spring"].values) == [10.0, 2.0] and ds.sizes["start"] == 1
    for name in ("grid_speed", "grid_fallen", "grid_gait_speed", "grid_compression",
                 "target_speed", "fitted_knee_spring", "fit_inside_grid", "residual_speed",
                 "residual", "configured_knee_spring", "configured_matches_fit"):
        assert name in ds and "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    fit = CAL.fit_log_linear(ds["knee_spring"].values, ds["grid_gait_speed"].values,
                             float(ds["target_speed"]))
    assert float(ds["fitted_knee_spring"]) == pytest.approx(fit["value"])
    assert float(ds["residual"]) == pytest.approx(
        abs(float(ds["residual_speed"]) - CAL.target_speed()))
    assert float(ds["configured_knee_spring"]) == config["ch4"]["model"]["knee_spring"]
    assert int(ds["configured_matches_fit"]) == int(
        abs(config["ch4"]["model"]["knee_spring"] - fit["value"])
        <= CAL.MATCH_TOLERANCE * fit["value"])
    # a softer knee spring compresses the stance leg more (§3.3.1.2's mechanism)
    comp = ds["grid_compression"].values[:, 0]
    assert comp[1] > comp[0]
    assert ds.attrs["solver_iterations"] == config["ch4"]["model"]["solver_iterations"]


def test_report_lists_the_grid_the_fit_and_whether_the_chapters_run_it(tiny):
    ds, _ = tiny
    t = RV.calibration_table({"model/calibration": ds})
    assert [r[-1] for r in t.rows][:2] == ["grid", "grid"] and t.rows[-1][-1].startswith("fit")
    assert "residual" in t.note and "calibration target" in t.note
    assert ("the fit." in t.note) == bool(int(ds["configured_matches_fit"]))
    assert RV.calibration_table({}).rows == [[RV.NOT_RUN] * 5]


def _calibration(fit=1.944, matches=1):
    return xr.Dataset(dict(fitted_knee_spring=((), fit),
                           configured_matches_fit=((), np.int8(matches))))


def test_claims_on_v1_s_speed_are_marked_as_resting_on_a_calibration_target():
    results = {"model/calibration": _calibration()}
    marked = [c for c in CLAIMS if MV.rests_on_oncilla(c.requires)
              and set(c.paper_keys) & set(TG.V1_PAPER_KEYS)]
    assert marked, "some ch3 claim compares with Tab. 3.1a's published speed"
    c = marked[0]
    mark = MV.flag(c.requires, results, "reproduced", c.paper_keys)["calibration_target"]
    assert mark["keys"] and mark["fitted_knee_spring"] == pytest.approx(1.944)
    out = {"id": c.id, "chapter": c.chapter, "status": "reproduced", "calibration_target": mark}
    assert MV.CALIBRATION_TARGET in MV.text(out)
    assert MV.CALIBRATION_TARGET in VD.claims_html([out])
    # no V1 key, or no calibration in the results: no mark
    other = next(c for c in CLAIMS if MV.rests_on_oncilla(c.requires)
                 and not set(c.paper_keys) & set(TG.V1_PAPER_KEYS))
    assert "calibration_target" not in MV.flag(other.requires, results, "reproduced",
                                               other.paper_keys)
    assert MV.flag(c.requires, {}, "reproduced", c.paper_keys) == {}
