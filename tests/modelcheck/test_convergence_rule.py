"""The three-valued convergence verdict (thesis.modelcheck.convergence_rule) on runs whose
answer is known: exact repeats converge, a real shift beyond the tolerance does not, and
draws too noisy to tell stay inconclusive."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.modelcheck import convergence_rule as CR


def _runs(speeds_by_setting, fell_by_setting=None):
    """(G, N) speeds and falls, case index (N,) from lists per setting of per-case lists."""
    G = len(speeds_by_setting)
    C = len(speeds_by_setting[0])
    n = len(speeds_by_setting[0][0])
    sp = np.array([[np.asarray(c, float) for c in s] for s in speeds_by_setting]).reshape(G, -1)
    if fell_by_setting is None:
        fell = np.zeros_like(sp, bool)
    else:
        fell = np.array([[np.asarray(c, bool) for c in s]
                         for s in fell_by_setting]).reshape(G, -1)
    return sp, fell, np.repeat(np.arange(C), n), C


def test_case_speed_is_the_mean_of_the_runs_up_and_needs_three():
    mean, se, n_up = CR.case_speeds([1.0, 2.0, 3.0, 9.0, 1.0, 1.0], [0, 0, 0, 1, 0, 1],
                                    [0, 0, 0, 0, 1, 1], 2)
    assert mean[0] == pytest.approx(2.0) and se[0] == pytest.approx(1.0 / np.sqrt(3))
    assert np.isnan(mean[1]) and n_up.tolist() == [3, 1]


def test_identical_deterministic_runs_converge():
    rng = np.random.default_rng(0)  # 100 runs per case: no fall in 100 bounds the rate
    base = [list(0.3 + 0.001 * rng.normal(size=100)),
            list(0.6 + 0.001 * rng.normal(size=100))]
    sp, fell, case, C = _runs([base, base, base])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["verdict"].tolist() == [CR.CONVERGED, CR.CONVERGED]
    np.testing.assert_allclose(res["speed_change"], 0.0, atol=1e-12)


def test_a_real_speed_shift_beyond_the_tolerance_is_not_converged():
    rng = np.random.default_rng(1)
    a = list(0.50 + 0.01 * rng.normal(size=20))
    b = list(0.60 + 0.01 * rng.normal(size=20))  # +20 %, spread 2 %
    sp, fell, case, C = _runs([[a], [b]])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["verdict"].tolist() == [CR.NOT_CONVERGED]
    assert res["speed_change_lower_k"][0, 0] > CR.SPEED_TOLERANCE


def test_a_shift_inside_the_noise_is_inconclusive_not_a_failure():
    rng = np.random.default_rng(2)
    a = list(0.50 + 0.15 * rng.normal(size=5))  # the chaotic spline: 30 % spread, 5 starts
    b = list(0.56 + 0.15 * rng.normal(size=5))
    sp, fell, case, C = _runs([[a], [b]])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["verdict"].tolist() == [CR.INCONCLUSIVE]


def test_fall_rate_change_is_decided_on_its_interval():
    n = 400  # many runs: a 20-point rise is beyond doubt, an equal rate is within
    up = [0.5] * n
    fell0 = [False] * n
    fell1 = [i < 0.2 * n for i in range(n)]
    sp, fell, case, C = _runs([[up], [up], [up]], [[fell0], [fell1], [fell0]])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["verdict"].tolist() == [CR.NOT_CONVERGED, CR.CONVERGED]
    assert res["fall_rate_change"][0] == pytest.approx(0.2)
    assert res["fall_rate_change_lower_k"][0] > CR.FALL_TOLERANCE
    # the same 20-point rise on 5 runs: the draws could give it
    sp, fell, case, C = _runs([[up[:5]], [up[:5]]], [[fell0[:5]], [[1, 0, 0, 0, 0]]])
    assert CR.compare_runs(sp, fell, case, C)["verdict"].tolist() == [CR.INCONCLUSIVE]


def test_agresti_caffo_keeps_error_on_a_case_that_never_fell():
    _, _, d, se = CR.fall_change([0] * 5, [0] * 5, [0] * 5, 1)
    assert d == 0.0 and se > 0.1  # 5 runs without a fall do not prove a rate of 0
    with pytest.raises(ValueError, match="case 1 has no runs"):
        CR.fall_change([0, 0], [0, 0], [0, 0], 2)


def test_a_gait_up_at_one_setting_only_blocks_converged():
    up = [0.5, 0.5, 0.5, 0.5]
    sp, fell, case, C = _runs([[up, up], [up, up]],
                              [[[0] * 4, [0] * 4], [[0] * 4, [1, 1, 0, 0]]])
    res = CR.compare_runs(sp, fell, case, C)
    assert np.isinf(res["speed_change"][0, 1]) and res["verdict"][0] != CR.CONVERGED


def test_paired_change_is_measured_within_each_run():
    # runs spread 30 % between them, but each run moves by exactly +4 % between settings:
    # unpaired this is inconclusive, paired the change is 4 % with almost no error
    rng = np.random.default_rng(3)
    v0 = 0.5 + 0.15 * rng.normal(size=40)
    v = 1.04 * v0 + 1e-4 * rng.normal(size=40)
    sp, fell, case, C = _runs([[list(v0)], [list(v)]])
    assert CR.compare_runs(sp, fell, case, C)["verdict"].tolist() == [CR.INCONCLUSIVE]
    r, se, pairs, one = CR.paired_speed_change(sp[1], sp[0], fell[1], fell[0], case, C)
    assert r[0] == pytest.approx(0.04, abs=1e-3) and se[0] < 1e-3
    assert pairs.tolist() == [40] and not one[0]
    res = CR.paired_followup(sp, fell, case, C)
    assert res["status"].tolist() == [[CR.INSIDE]]
    # the ratio estimator's error by hand on three pairs
    r, se, _, _ = CR.paired_speed_change([2.0, 4.0, 7.0], [1.0, 2.0, 3.0], [0, 0, 0],
                                         [0, 0, 0], [0, 0, 0], 1)
    d = np.array([2.0, 4.0, 7.0]) - 13 / 6 * np.array([1.0, 2.0, 3.0])
    assert r[0] == pytest.approx(13 / 6 - 1)
    assert se[0] == pytest.approx(d.std(ddof=1) / np.sqrt(3) / 2.0)


def test_paired_change_uses_only_runs_up_at_both_settings():
    v0, v = [0.5, 0.5, 0.5, 0.5, 9.0], [0.6, 0.6, 0.6, 9.0, 0.6]
    r, _, pairs, one = CR.paired_speed_change(v, v0, [0, 0, 0, 1, 0], [0, 0, 0, 0, 1],
                                              [0] * 5, 1)
    assert pairs.tolist() == [3] and r[0] == pytest.approx(0.2) and not one[0]
    # up three times at the reference, once at the refined setting: a speed at one only
    r, _, pairs, one = CR.paired_speed_change(v, v0, [1, 1, 0, 1, 1], [0, 0, 0, 0, 1],
                                              [0] * 5, 1)
    assert np.isnan(r[0]) and one[0]
    res = CR.paired_followup(np.array([v0, v]), np.array([[0, 0, 0, 0, 1], [1, 1, 0, 1, 1]],
                                                         bool), np.zeros(5, int), 1)
    assert np.isinf(res["speed_change"][0, 0]) and res["status"][0, 0] == CR.MOVED


def test_case_status_reads_both_interval_ends():
    st = CR.case_status([0.02, 0.30, 0.08, np.inf, np.nan], [0.05, 0.40, 0.20, np.nan, np.nan],
                        [0.0, 0.20, 0.01, np.nan, np.nan])
    assert st.tolist() == [CR.INSIDE, CR.BEYOND, CR.UNDECIDED, CR.MOVED, CR.UNTESTED]


@pytest.mark.parametrize("followup, fall_upper, fall_lower, want", [
    ([[CR.INSIDE], [CR.INSIDE]], 0.03, 0.0, [CR.CONVERGED, CR.CONVERGED]),
    ([[CR.INSIDE], [CR.UNDECIDED]], 0.03, 0.0, [CR.CONVERGED, CR.INCONCLUSIVE]),
    ([[CR.BEYOND], [CR.INSIDE]], 0.03, 0.0, [CR.NOT_CONVERGED, CR.CONVERGED]),
    ([[CR.MOVED], [CR.INSIDE]], 0.03, 0.0, [CR.INCONCLUSIVE, CR.CONVERGED]),
    ([[CR.INSIDE], [CR.INSIDE]], 0.08, 0.0, [CR.INCONCLUSIVE, CR.INCONCLUSIVE]),
    ([[CR.INSIDE], [CR.INSIDE]], 0.09, 0.06, [CR.NOT_CONVERGED, CR.NOT_CONVERGED]),
])
def test_two_stage_replaces_the_followed_cases_only(followup, fall_upper, fall_lower, want):
    # case 1 was undecided at the first refined setting; cases 0 and 2 were decided
    status = [[CR.INSIDE, CR.UNDECIDED, CR.UNTESTED], [CR.INSIDE, CR.INSIDE, CR.UNTESTED]]
    got = CR.two_stage(status, [fall_upper] * 2, [fall_lower] * 2, [1], followup)
    assert got.tolist() == want
    # without a follow-up the undecided case keeps the first setting inconclusive
    assert CR.two_stage(status, [0.03] * 2, [0.0] * 2, [], np.empty((2, 0))).tolist() == [
        CR.INCONCLUSIVE, CR.CONVERGED]


def test_falls_that_cancel_over_cases_are_decided_per_case():
    # case 0 falls 30 points more, case 1 30 points less: the rate over all runs is unchanged
    n = 300
    up = [0.5] * n
    lo = [i < 0.2 * n for i in range(n)]
    hi = [i < 0.5 * n for i in range(n)]
    sp, fell, case, C = _runs([[up, up], [up, up]], [[lo, hi], [hi, lo]])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["fall_rate_change"][0] == pytest.approx(0.0)
    assert res["fall_rate_change_upper"][0] < 0.06  # pooled: recorded, it would hide them
    np.testing.assert_allclose(res["case_fall_rate_change"][0], 0.3)
    assert np.all(res["case_fall_rate_change_lower_k"][0] > CR.CASE_FALL_TOLERANCE)
    assert res["verdict"].tolist() == [CR.NOT_CONVERGED]
    assert res["quantities"][0] == 2 + 2  # two speeds, two cases' falls


def test_a_case_that_never_falls_in_thirty_runs_bounds_its_fall_rate():
    up = [0.5] * 30
    sp, fell, case, C = _runs([[up], [up]])
    res = CR.compare_runs(sp, fell, case, C)
    assert res["case_fall_rate_change_upper"][0, 0] < 0.10 < CR.CASE_FALL_TOLERANCE
    assert res["verdict"].tolist() == [CR.CONVERGED]
    # a gait that stands in all 30 runs and falls in 18 at the refined setting moved
    sp, fell, case, C = _runs([[up], [up]], [[[False] * 30], [[i < 18 for i in range(30)]]])
    assert CR.compare_runs(sp, fell, case, C)["verdict"].tolist() == [CR.NOT_CONVERGED]


def test_the_table_s_own_speed_tolerance_decides():
    rng = np.random.default_rng(3)
    a = list(0.50 + 0.005 * rng.normal(size=40))
    b = list(0.53 + 0.005 * rng.normal(size=40))  # +6 %, spread 1 %
    sp, fell, case, C = _runs([[a], [b]])
    assert CR.compare_runs(sp, fell, case, C)["verdict"].tolist() == [CR.CONVERGED]
    assert CR.compare_runs(sp, fell, case, C, speed_tol=0.03)["verdict"].tolist() == [
        CR.NOT_CONVERGED]


def test_starts_to_decide_projects_the_interval_with_the_runs():
    z, z_k = 1.96, 2.5
    need = CR.starts_to_decide([0.01, 0.05, 0.03, np.inf, np.nan], [0.02, 0.02, 0.01, 0.1, 0.1],
                               30, 0.03, z, z_k)
    assert need[0] == pytest.approx(30 * (z * 0.02 / 0.02) ** 2)   # inside: 1.96 se in 2 %
    assert need[1] == pytest.approx(30 * (z_k * 0.02 / 0.02) ** 2)  # beyond: 2.5 se past 3 %
    assert np.isinf(need[2]) and need[3] == 30 and np.isnan(need[4])
    # already decided: no more runs needed than these
    assert CR.starts_to_decide([0.0], [0.001], 30, 0.03, z, z_k)[0] == 30
    # a noisy inconclusive case: the projection, run, decides it
    rng = np.random.default_rng(4)
    a, b = 0.5 + 0.05 * rng.normal(size=(2, 10))
    b = b * 1.08
    sp, fell, case, C = _runs([[list(a)], [list(b)]])
    res = CR.compare_runs(sp, fell, case, C, speed_tol=0.03)
    assert res["verdict"].tolist() == [CR.INCONCLUSIVE]
    assert res["starts_to_decide"][0, 0] > 10


def test_two_stage_reads_each_case_s_fall_rate():
    status = [[CR.INSIDE, CR.INSIDE]]
    ok = CR.two_stage(status, [0.03], [0.0], [], np.empty((1, 0)), [[0.1, 0.1]], [[0.0, 0.0]])
    wide = CR.two_stage(status, [0.03], [0.0], [], np.empty((1, 0)), [[0.1, 0.2]], [[0.0, 0.0]])
    far = CR.two_stage(status, [0.03], [0.0], [], np.empty((1, 0)), [[0.1, 0.6]], [[0.0, 0.2]])
    assert (ok.tolist(), wide.tolist(), far.tolist()) == (
        [CR.CONVERGED], [CR.INCONCLUSIVE], [CR.NOT_CONVERGED])
