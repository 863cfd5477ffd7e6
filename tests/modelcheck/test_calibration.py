"""The committed calibration of the Oncilla's knee spring (thesis.modelcheck.calibration,
``thesis validate oncilla --only calibration``): the procedure's fit on known numbers and
the marks and tables it feeds (the procedure end to end is checked on the smoke pipeline's
result, tests/pipeline/layouts_model.py). No test asserts the fitted value of the current
model (that is what the procedure reports)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from thesis.claims import CLAIMS, model_validity as MV
from thesis.modelcheck import calibration as CAL
from thesis.modelcheck import split as S
from thesis.modelcheck import targets as TG
from thesis.report import verdicts as VD


def test_target_is_the_midpoint_of_the_thesis_s_two_speeds_of_tab3_1a():
    assert CAL.target_speed() == pytest.approx(0.5 * (0.27 + 0.30))
    case = CAL.v1_case()
    assert case["gait"] == "tab3_1a" and case["frequency"] == TG.V1_FREQUENCY == 1.5


def test_every_bracket_of_a_non_monotone_grid_is_found_stiffest_first():
    grid = [10.0, 5.0, 3.0, 2.0, 1.5, 1.0]
    speeds = [0.460, 0.272, 0.356, 0.301, 0.256, 0.014]
    assert CAL.brackets(grid, speeds, 0.285) == [
        (10.0, 5.0, 0.460, 0.272), (5.0, 3.0, 0.272, 0.356), (2.0, 1.5, 0.301, 0.256)]
    # the order of the grid does not matter; a fallen point (NaN) brackets nothing
    assert CAL.brackets(grid[::-1], speeds[::-1], 0.285) == CAL.brackets(grid, speeds, 0.285)
    assert CAL.brackets([10.0, 5.0, 2.0], [0.45, np.nan, 0.20], 0.30) == []
    assert CAL.brackets([10.0, 5.0], [0.45, 0.40], 0.285) == []


def test_log_secant_crosses_zero_on_the_line_in_log_k():
    k = CAL.log_secant(2.0, 1.5, 0.2897 - 0.285, 0.242 - 0.285)
    t = (0.285 - 0.2897) / (0.242 - 0.2897)
    assert k == pytest.approx(math.exp(math.log(2.0) + t * (math.log(1.5) - math.log(2.0))))
    assert 1.5 < k < 2.0
    assert CAL.log_secant(4.0, 2.0, 0.0, -0.1) == pytest.approx(4.0)
    assert CAL.log_secant(4.0, 2.0, 0.1, 0.1) == 4.0


def test_refine_finds_the_crossing_of_a_known_response_within_the_band():
    # speed linear in log k: v = 0.1 + 0.1 ln k, crossing 0.285 at k = exp(1.85)
    calls = []

    def measure(k):
        calls.append(k)
        return 0.1 + 0.1 * math.log(k), True

    b = CAL.brackets([10.0, 5.0], [measure(10.0)[0], measure(5.0)[0]], 0.285)[0]
    calls.clear()
    runs = CAL.refine(measure, b, 0.285, (0.284, 0.286), steps=4)
    assert len(runs) == 1 == len(calls)  # exact in log k: one secant step
    assert runs[0][0] == pytest.approx(math.exp(1.85))
    # a curved response: Illinois keeps the crossing bracketed and approaches it
    runs = CAL.refine(lambda k: (0.05 * k ** 1.5, True),
                      (5.0, 2.0, 0.05 * 5 ** 1.5, 0.05 * 2 ** 1.5),
                      0.285, (0.2849, 0.2851), steps=20)
    want = (0.285 / 0.05) ** (1 / 1.5)
    assert abs(runs[-1][0] - want) < 1e-3 and len(runs) < 20
    assert all(2.0 <= k <= 5.0 for k, _ in runs)


def test_refine_stops_at_a_fall_and_skips_a_bracket_with_an_end_in_the_band():
    runs = CAL.refine(lambda k: (float("nan"), False), (10.0, 5.0, 0.45, 0.2), 0.285,
                      (0.27, 0.30), 4)
    assert len(runs) == 1 and math.isnan(runs[0][1])
    assert CAL.refine(lambda k: 1 / 0, (10.0, 5.0, 0.29, 0.2), 0.285, (0.27, 0.30), 4) == []
    assert CAL.refine(lambda k: 1 / 0, (10.0, 5.0, 0.45, 0.2), 0.285, (0.27, 0.30), 0) == []


def test_refine_goes_on_past_runs_in_the_band_whose_starts_disagree():
    # an end in the band whose starts disagree does not end the bracket
    seen = []

    def measure(k):
        seen.append(k)
        return 0.28, len(seen) >= 2  # in the band; the first run's starts disagree

    runs = CAL.refine(measure, (10.0, 5.0, 0.29, 0.2), 0.285, (0.27, 0.30), 4,
                      ends_agree=(False, True))
    assert len(runs) == 2 == len(seen)


def test_starts_agree_within_the_thesis_s_two_speeds_and_none_fallen():
    w = CAL.agreement_width()
    assert w == pytest.approx(0.03)
    assert CAL.starts_agree([0.30, 0.30, 0.30], [0, 0, 0], w)
    assert CAL.starts_agree([0.301, 0.317, 0.302], [0, 0, 0], w)
    # the former fit's starts (5.105 N m/rad): a spread of 0.146 m/s
    assert not CAL.starts_agree([0.370, 0.224, 0.236], [0, 0, 0], w)
    assert not CAL.starts_agree([0.30, 0.30, 0.30], [0, 1, 0], w)
    assert not CAL.starts_agree([0.30, np.nan], [0, 0], w)


def test_choose_takes_the_run_nearest_the_target_and_the_earliest_on_a_tie():
    assert CAL.choose([0.46, 0.272, np.nan, 0.29], 0.285) == 3
    assert CAL.choose([0.5, 0.25], 0.375) == 0  # exact tie in binary
    with pytest.raises(ValueError, match="every run fell"):
        CAL.choose([np.nan, np.nan], 0.285)


def test_choose_takes_only_runs_whose_starts_agree_unless_none_does():
    # the former calibration's runs: 5.105 (0.277, starts disagree) was nearest
    speeds = [0.459, 0.265, 0.357, 0.300, 0.255, 0.014, 0.277]
    agree = [True, False, True, True, True, True, False]
    assert CAL.choose(speeds, 0.285) == 6
    assert CAL.choose(speeds, 0.285, agree) == 3
    assert CAL.choose(speeds, 0.285, [False] * 7) == 6


def test_target_band_is_the_thesis_s_two_speeds():
    assert CAL.target_band() == pytest.approx((0.27, 0.30))


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


def test_with_the_fit_every_claim_on_a_fitted_number_is_marked_from_the_fit():
    fitted = S.paper_keys(S.FITTED)
    assert set(TG.V1_PAPER_KEYS) <= fitted and len(fitted) > len(TG.V1_PAPER_KEYS)
    fit = xr.Dataset(dict(fit_knee_spring=((), 3.1),
                          configured_matches_fit=(("parameter",), np.int8([1, 1, 0]))))
    results = {"model/calibration": _calibration(), "model/fit": fit}
    on_oncilla = [c for c in CLAIMS if MV.rests_on_oncilla(c.requires)]
    marked = [c for c in on_oncilla if set(c.paper_keys) & fitted]
    assert marked
    for c in on_oncilla:
        mark = MV.flag(c.requires, results, "reproduced", c.paper_keys).get(
            "calibration_target")
        assert (mark is not None) == (c in marked), c.id
        if mark:  # the fit supersedes the V1 calibration, and one unmatched value shows
            assert mark["source"] == "model/fit" and mark["fitted_knee_spring"] == 3.1
            assert mark["configured_matches_fit"] is False
            assert set(mark["keys"]) == set(c.paper_keys) & fitted
            assert "model/fit" in MV.text({"calibration_target": mark})
