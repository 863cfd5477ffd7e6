"""The Oncilla validation instrument (thesis.modelcheck.validation, ``thesis validate
oncilla``): its measurements on cases where the answer is known (the instrument end to end
is checked on the smoke pipeline's result, tests/pipeline/layouts_model.py). No test
asserts a target's outcome on the current model (that is what the instrument reports, not
what the code guarantees)."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest
import xarray as xr

from thesis.config import load_config
from thesis.gaits import conditions as C
from thesis.gaits import trajectories as T
from thesis.modelcheck import checks as M
from thesis.modelcheck import targets as TG
from thesis.modelcheck import validation as V


def _rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def test_trunk_angles_read_roll_and_pitch():
    roll, pitch = V.trunk_angles(np.stack([_rot_x(0.3), _rot_y(0.2), np.eye(3)]))
    np.testing.assert_allclose(roll, [0.3, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(pitch, [0.0, 0.2, 0.0], atol=1e-12)


def test_cases_run_every_flat_published_gait_at_the_frequencies_and_its_own():
    cs = V.cases({"frequencies": [1.5, 2.6]})
    flat = [g for g in TG.published_gaits() if g.flat]
    got = {(c["gait"], c["frequency"]) for c in cs}
    for g in flat:
        fam = T.FAMILIES[g.family]()
        own = g.params[fam.index("f")]
        assert {(g.name, 1.5), (g.name, 2.6), (g.name, own)} <= got
    c = next(c for c in cs if c["gait"] == "tab3_1b" and c["frequency"] == 2.6)
    fam = T.SplineGait()
    assert c["params"][fam.index("f")] == 2.6 and c["params"][fam.index("a")] == 91.0


def test_start_kicks_are_seeded_and_sized():
    a = V.start_kicks(2018, 400, 0.05)
    np.testing.assert_array_equal(a, V.start_kicks(2018, 400, 0.05))
    assert a.shape == (400, 3) and np.std(a) == pytest.approx(0.05, rel=0.1)
    assert not np.allclose(a, V.start_kicks(2019, 400, 0.05))


def test_commanded_toes_are_the_targets_the_commands_reach():
    """Forward kinematics of the commanded joint angles gives back the foot targets the
    IK was asked for, where they are reachable (Tab. 3.1a's half ellipse)."""
    fam = T.EllipseGait()
    p = jnp.asarray(next(g for g in TG.published_gaits() if g.name == "tab3_1a").params)
    phases = np.linspace(0.0, 1.0, 7, endpoint=False)
    cmd = np.stack([np.asarray(fam.commands_at_phase(p, x)) for x in phases])[None]
    want = np.stack([np.asarray(fam.foot_targets(p, x)) for x in phases])[None]
    np.testing.assert_allclose(V.commanded_toes(fam, cmd), want, atol=1e-3)


def test_toes_of_the_build_state_sit_build_depth_below_the_hips():
    model, state = C.base_model(load_config("smoke")["ch4"])
    sim = dict(pos=np.asarray(state.pos)[None, None], rot=np.asarray(state.rot)[None, None])
    toe = V.toe_in_hip_frames(model, sim)[0, 0]
    np.testing.assert_allclose(toe, np.tile([0.0, 0.0, -M.O.BUILD_DEPTH], (4, 1)), atol=1e-4)


def test_reach_inside_and_outside():
    he = next(g for g in TG.published_gaits() if g.name == "tab3_1a")
    np.testing.assert_array_equal(V.reach("ellipse", he.params), np.zeros((3, 4)))
    p = np.array(he.params)
    p[T.EllipseGait().index("x0")] = 300.0  # far below any leg's reach
    np.testing.assert_array_equal(V.reach("ellipse", p), np.ones((3, 4)))
    p = np.array(he.params)
    fam = T.EllipseGait()
    p[fam.index("b_fore")] = 120.0  # a swing far above the fore legs' flexion stop
    r = V.reach("ellipse", p)
    assert V.PATH_PARTS == ("cycle", "stance", "swing")
    np.testing.assert_array_equal(r[1], 0.0)  # the stance stays reachable
    assert np.all(r[2, :2] > 0.2) and np.all(r[2, 2:] == 0.0)  # fore swings only
    assert r[0, 0] == pytest.approx(0.5 * r[2, 0], abs=0.02)  # duty 0.5
    assert np.isnan(V.reach("sine", np.zeros(13))).all()


def test_stance_at_stops_counts_the_stance_samples_on_each_stop():
    model, _ = C.base_model(load_config("smoke")["ch4"])
    hi = np.asarray(model.limit_hi, np.float64)
    lim = list(np.asarray(model.limit_dof))
    knee = model.dof("LF_knee:0")
    cable = model.dof("RH_cable:0")
    q = np.zeros((2, 10, model.n_dof))
    # run 0: LF's knee motor on its stop in samples 0-3, 0.02 rad short of it in 4-9
    q[0, :4, knee] = hi[lim.index(knee)]
    q[0, 4:, knee] = hi[lim.index(knee)] - 0.02
    # run 1: RH's cable beyond its stop throughout (taut and stretched)
    q[1, :, cable] = hi[lim.index(cable)] + 0.005
    stance = np.ones((2, 10, 4), bool)
    stance[0, 2:4, 0] = False        # two of LF's on-stop samples are swing: not counted
    stance[1, :, 1] = False          # RF never in stance: NaN
    out = V.stance_at_stops(model, q, stance)
    assert set(out) == set(V.STOPS)
    np.testing.assert_allclose(out["knee_stop"][0, 0], 2 / 8)
    assert out["knee_stop"][0, 2] == 0.0 and out["cable_taut"][1, 3] == 1.0
    assert np.isnan(out["knee_stop"][1, 1]) and np.isnan(out["cable_taut"][1, 1])
    # the build pose (all coordinates 0) has the cable taut and the knee motor off its stop
    assert np.all(out["cable_taut"][0] == 1.0) and out["knee_stop"][1, 0] == 0.0


def test_settings_variables_carry_the_rule_s_verdict_and_intervals():
    rng = np.random.default_rng(0)
    n = 100  # enough runs without a fall to bound the fall rate within 5 points
    speeds = np.stack([np.r_[0.3 + 0.001 * rng.normal(size=n), 0.5 + 0.001 * rng.normal(size=n)]
                       for _ in range(3)])
    speeds[2, n:] *= 1.5  # the second case 50 % faster at the third setting
    fells = np.zeros_like(speeds, bool)
    case = np.repeat([0, 1], n)
    data, verdicts = V.settings_variables(speeds, fells, case, 2, [0.002, 0.001, 0.002],
                                          [30, 30, 60], [1.0, 2.0, 2.0])
    assert verdicts.tolist() == ["converged", "not converged"]
    for name, (dims, values, attrs) in data.items():
        assert "units" in attrs and "long_name" in attrs, name
    assert data["speed_change"][1].shape == (2, 2)
    assert data["max_speed_change"][1][1] == pytest.approx(0.5, rel=0.02)
    assert V.verdict_attrs(verdicts)["verdict"] == "not converged"
    assert V.verdict_attrs(["converged", "inconclusive"])["verdict"] == "inconclusive"


def test_validate_verb_refuses_what_it_cannot_do():
    from thesis import cli

    with pytest.raises(SystemExit, match="unknown robot"):
        cli.main(["validate", "arm4", "--profile", "smoke"])
    with pytest.raises(SystemExit, match="--output needs --only"):
        cli.main(["validate", "oncilla", "--profile", "smoke", "--output", "x.nc"])


def test_the_convergence_table_names_the_case_whose_falls_moved_and_the_starts_to_decide():
    from thesis.report import validation as RV

    n = 200  # case 0 stands at dt and falls in half its runs at dt / 2; case 1 never falls
    rng = np.random.default_rng(5)
    sp = 0.3 + 0.05 * rng.normal(size=(3, 2 * n))
    fells = np.zeros((3, 2 * n), bool)
    fells[1, : n // 2] = True
    case = np.repeat([0, 1], n)
    data, verdicts = V.settings_variables(sp, fells, case, 2, [0.002, 0.001, 0.002], [20, 20, 40],
                                          [1.0, 2.0, 2.0], speed_tol=0.03)
    ds = xr.Dataset(data, coords=dict(setting=[s[0] for s in V.SETTINGS],
                                      refined=[s[0] for s in V.SETTINGS[1:]], case=[0, 1],
                                      case_gait=("case", ["tab3_1a", "tab3_1b"]),
                                      case_frequency=("case", [1.0, 1.5])))
    ds.attrs.update(starts=n, **V.verdict_attrs(verdicts, 0.03))
    assert verdicts[0] == "not converged"
    t = RV.convergence_table({"model/convergence": ds})
    assert t.rows[1][5].startswith("tab3_1a at 1 Hz: 50.0 (>= ")
    assert "15 points" in t.note and "3 %" in t.note
    # five starts: the 2x-sweeps setting is undecided and says how many would decide it
    few = V.settings_variables(sp[:, ::40], fells[:, ::40], case[::40], 2, [0.002] * 3,
                               [20] * 3, [1.0] * 3, speed_tol=0.03)[0]
    need = few["starts_to_decide"][1]
    assert np.all(np.isfinite(need[1])) and np.all(need[1] > 5)
