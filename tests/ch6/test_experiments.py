"""Teacher choice, the sweep's dataset from recordings and the Fig. 6.6 join, without
simulating (synthetic recordings and datasets)."""

from __future__ import annotations

import logging

import numpy as np
import pytest
import xarray as xr

from thesis import claims
from thesis.config import load_config
from thesis.ch6 import experiments as E
from thesis.ch6 import loop
from thesis.ch6 import protocol as PR
from thesis.ch6 import sweep as S
from thesis.ch6 import teacher as TE
from thesis.runctx import RunContext

CFG = dict(
    seeds=[0, 1, 2], model=dict(dt=0.00205, solver_iterations=30, knee_spring=10.0,
                                joint_hz=1.0 / 0.00205, contact_hz=0.25 / 0.00205),
    control=dict(substeps=4, input_noise=0.01, jitter=0.15, encoder_counts=4096,
                 encoder_noise=0.5),
    protocol=dict(settle=0.5, normalisation=1.0, stage_seconds=2.0, running=4.0,
                  power_off=0.5, recovery=3.0),
    criteria=dict(fall_height=0.08, window=2.0, amplitude_min=0.5, amplitude_max=2.0,
                  frequency_tolerance=0.1, autocorrelation_min=0.5, recovery_within=1.0,
                  min_speed=0.05),
    record=dict(mse_interval=0.05, joint_space_seconds=1.0))


def test_choose_prefers_passing_then_longest_upright():
    assert TE.choose([0, 1, 1], [10, 10, 10], [0.5, 0.1, 0.2]) == 2
    assert TE.choose([0, 0, 0], [3.0, 9.0, 9.0], [0.9, 0.1, 0.2]) == 2
    assert TE.choose([0, 1], [1.0, 1.0], [np.nan, np.nan]) == 1


def test_candidate_params():
    fam = TE.family("spline")
    names = ["t_stance_f" if n == "duty" else n for n in fam.names]
    p0 = np.array([1.9, 60.0, 140.0, 0.0, -5.0, 0.5, 30.0, 20.0, 25.0, 35.0, 10.0, 5.0])
    table = xr.Dataset({"value": (("gait", "parameter", "seed"), p0[None, :, None])},
                       coords=dict(gait=["spline"], parameter=names, seed=[0]))
    p = TE.candidate_params(table, "spline", 0, 1.7, 0.5)
    assert p[fam.index("f")] == 1.7 and p[fam.index("a")] == pytest.approx(30.0)
    w = TE.candidate_params(table, "spline", 0, 1.7, 1.0, duty=0.75)
    assert w[fam.index("duty")] == 0.75 and w[fam.index("a")] == pytest.approx(60.0)
    with pytest.raises(ValueError, match="teacher family"):
        TE.family("sine")


def _fixed(params=None, family="half_ellipse"):
    p = dict(x0=145.0, y0_fore=0.0, y0_hind=20.0, a=60.0, b_fore=50.0, b_hind=10.0)
    return dict(family=family, params=p if params is None else params)


def test_fixed_params_take_frequency_and_walk_duty_from_the_config():
    fam = TE.family("half_ellipse")
    name, p = TE.fixed_params(_fixed(dict(_fixed()["params"], duty=0.55)), "trot", 1.7)
    assert name == "half_ellipse" and p[fam.index("f")] == 1.7
    assert p[fam.index("duty")] == 0.55 and p[fam.index("a")] == 60.0
    _, w = TE.fixed_params(_fixed(), "walk", 1.7, duty=0.75)  # outside the trot's box
    assert w[fam.index("duty")] == 0.75 and w[fam.index("x0")] == 145.0


def test_fixed_params_name_the_key_and_what_is_wrong():
    with pytest.raises(ValueError, match=r"ch6.teacher.fixed.trot.params.*missing \['duty'\]"):
        TE.fixed_params(_fixed(), "trot", 1.7)
    extra = dict(_fixed()["params"], duty=0.75)
    with pytest.raises(ValueError, match=r"ch6.teacher.fixed.walk.params.*not allowed \['duty'\]"):
        TE.fixed_params(_fixed(extra), "walk", 1.7, duty=0.75)
    far = dict(_fixed()["params"], a=500.0)  # beyond a_max(x0)
    with pytest.raises(ValueError, match=r"'a'\] lie outside the half_ellipse"):
        TE.fixed_params(_fixed(far), "walk", 1.7, duty=0.75)
    with pytest.raises(ValueError, match="teacher family"):
        TE.fixed_params(_fixed(family="sine"), "walk", 1.7, duty=0.75)


def _screen_config(**teacher):
    """The smoke ch6 section with a protocol of a few seconds and no perturbed twins."""
    cfg = load_config("smoke", overrides={"ch6": {
        "teacher": teacher, "perturbation": {"relative": 0.0},
        "protocol": dict(settle=0.25, normalisation=0.5, stage_seconds=0.5, running=1.0,
                         power_off=0.25, recovery=1.0),
        "walk": {"stage_seconds": 0.5}, "criteria": {"window": 0.5, "recovery_within": 0.5}}})
    return cfg["ch6"]


def test_teacher_fixed_runs_the_configured_gaits_and_screen_reads_chapter3(tmp_path):
    """source fixed: the two configured teachers, no chapter 3 input; source screen: ch3's
    optima, and the optimum the fixed trot was made of gives the same open-loop run."""
    cfg = _screen_config(source="fixed")
    ctx = lambda c, inputs: RunContext(  # noqa: E731
        key="ch6/teacher", profile="smoke", config=c, full_config={"root_seed": 2018},
        inputs=inputs, log=logging.getLogger("test"))
    fixed = E.teacher(ctx(cfg, {}))
    assert list(fixed["candidate"].values) == ["trot/half_ellipse/fixed",
                                               "walk/half_ellipse/fixed"]
    assert fixed.attrs["teacher_source"] == "fixed"
    assert list(fixed["candidate_source_seed"].values) == [-1, -1]
    trot = cfg["teacher"]["fixed"]["trot"]["params"]
    got = fixed["teacher_params"].sel(gait="trot")
    for name, value in trot.items():
        assert float(got.sel(parameter=name)) == value
    assert float(got.sel(parameter="f")) == 1.7
    assert float(fixed["teacher_params"].sel(gait="walk", parameter="duty")) == 0.75

    fam = TE.family("half_ellipse")
    names = ["t_stance_f" if n == "duty" else n for n in fam.names]
    row = [trot.get(n, 1.7) for n in fam.names]  # f: any value, the screen sets 1.7
    table = xr.Dataset({"value": (("gait", "parameter", "seed"), np.array(row)[None, :, None])},
                       coords=dict(gait=["half_ellipse"], parameter=names, seed=[4]))
    table.to_netcdf(tmp_path / "table3_1.nc", engine="h5netcdf")
    scfg = _screen_config(source="screen", families=["half_ellipse"], stride_scales=[1.0])
    with pytest.raises(KeyError, match="table3_1"):
        E.teacher(ctx(scfg, {}))
    screen = E.teacher(ctx(scfg, {"table3_1": tmp_path / "table3_1.nc"}))
    assert list(screen["candidate"].values) == ["trot/half_ellipse/seed4/stride1",
                                                "walk/half_ellipse/seed4/stride1"]
    assert screen.attrs["teacher_source"] == "screen" and screen.attrs["seeds"] == [4]
    np.testing.assert_array_equal(screen["teacher_params"].sel(gait="trot"),
                                  fixed["teacher_params"].sel(gait="trot"))
    for k in ("up_seconds", "speed", "passed"):
        np.testing.assert_array_equal(screen[f"candidate_{k}"][0], fixed[f"candidate_{k}"][0])


def _teachers():
    fam = TE.family("half_ellipse")
    p = np.array([140.0, 5.0, -10.0, 40.0, 20.0, 25.0, 0.55, 1.7])
    return {"trot": (fam, p, 1.7)}


def _fake_recordings(runs, scheds, dt, good):
    """Recordings of a controller that reproduces the teacher (``good``) or stays still."""
    n = len(runs)
    steps = runs[0]["share"].shape[0]
    y = np.stack([r["teacher"] if g else np.zeros_like(r["teacher"]) for r, g in zip(runs, good)])
    pos = np.zeros((n, steps, 3))
    pos[:, :, 0] = 0.2 * np.arange(steps) * dt
    pos[:, :, 2] = 0.15
    enc = y[:, :, list(loop.HIP_KNEE)]
    return dict(y_hat=y.astype(np.float32), encoders=enc, trunk_pos=pos,
                trunk_up=np.ones((n, steps)))


def test_sweep_dataset_layout_and_outcomes():
    conds = [S.Condition("h20_b2", "trot", 20, 2, 2.0, 2.0, 0.5),
             S.Condition("linear", "trot", 0, 0, 2.0, 2.0, 0.5, linear=True)]
    teachers = _teachers()
    runs, labels, scheds, tables, n = S.build_runs(conds, [0, 1, 2], teachers, CFG, 2018)
    assert len(runs) == 6 and labels[3] == ("linear", 0)
    assert runs[0]["w_hidden"].shape == (20, 8) and runs[0]["slot_mask"].sum() == 3
    assert runs[3]["identity"] and runs[3]["hidden_mask"].sum() == 8
    np.testing.assert_array_equal(runs[0]["w_hidden"], runs[3]["w_hidden"])  # same seed
    assert runs[0]["noise_seed"] != runs[1]["noise_seed"]
    dt = S.controller_dt(CFG)
    rec = _fake_recordings(runs, scheds, dt, good=[True] * 3 + [False] * 3)
    timing = dict(compile_seconds=1.0, rollout_seconds=2.0)
    ds = S.evaluate(rec, runs, conds, [0, 1, 2], scheds, teachers, CFG, timing,
                    thesis_ref="test", joint_space=True)
    assert list(ds["success"].sel(config="h20_b2").values) == [1, 1, 1]
    assert set(ds["outcome"].sel(config="linear").values) == {"dies_out"}
    assert list(ds["n_signals"].values) == [61, 9] and list(ds["hidden"].values) == [20, 0]
    assert ds["robot_seconds_per_wall_second"].attrs["measurement"] == "wall_clock"
    assert ds["rh_teacher"].shape == (2, 3, PR.n_steps(1.0, dt), 2)
    assert float(ds["train_mse"].sel(config="h20_b2").max()) == 0.0  # perfect output
    assert ds.attrs["protocol_running"] == 4.0
    for name, var in ds.data_vars.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name


def _ctx(inputs, config):
    return RunContext(key="ch6/fig6_6", profile="smoke", config=config,
                      full_config={"root_seed": 2018}, inputs=inputs,
                      log=logging.getLogger("test"))


def test_fig6_6_joins_the_sweeps(tmp_path):
    conds = {"linear_feedback": [S.Condition("linear", "trot", 0, 0, 2.0, 2.0, 0.5, True)],
             "trot": [S.Condition("h50_b5", "trot", 50, 5, 2.0, 2.0, 0.5)],
             "minimal_hidden": [S.Condition(f"h{h}_b0", "trot", h, 0, 2.0, 2.0, 0.5)
                                for h in (32, 128)],
             "minimal_buffer": [S.Condition(f"h12_b{b}", "trot", 12, b, 2.0, 2.0, 0.5)
                                for b in (0, 16)]}
    inputs = {}
    dt = S.controller_dt(CFG)
    for name, cs in conds.items():
        runs, _, scheds, _, _ = S.build_runs(cs, [0, 1, 2], _teachers(), CFG, 2018)
        rec = _fake_recordings(runs, scheds, dt, good=[True] * len(runs))
        ds = S.evaluate(rec, runs, cs, [0, 1, 2], scheds, _teachers(), CFG,
                        dict(compile_seconds=1.0, rollout_seconds=1.0), thesis_ref="t")
        inputs[name] = tmp_path / f"{name}.nc"
        ds.to_netcdf(inputs[name], engine="h5netcdf")
    curves = [dict(source="minimal_hidden", config="h128_b0", kind="no_window"),
              dict(source="minimal_buffer", config="h12_b0", kind="too_few_signals")]
    out = E.fig6_6(_ctx(inputs, {"fig6_6": {"curves": curves}}))
    assert out.sizes["setting"] == 6 and out.sizes["curve"] == 2
    assert "trot/h50_b5" in out["setting"].values
    assert list(out["curve_kind"].values) == ["no_window", "too_few_signals"]
    assert out.attrs["protocol_running"] == 4.0
    v = claims.get("ch6.signal_count_determines_performance").check({"ch6/fig6_6": out})
    assert v.status == "inconclusive"  # a 4-s running stage cannot test "stable for 30 s"
    bad = [dict(source="minimal_hidden", config="h64_b0", kind="no_window")]
    with pytest.raises(KeyError, match="h64_b0"):
        E.fig6_6(_ctx(inputs, {"fig6_6": {"curves": bad}}))


def test_screen_metrics():
    sch = PR.Schedule(0.5, 1.0, 2.0, 2.0, 4.0, 0.5, 3.0)
    dt = 0.0082
    n = PR.n_steps(sch.total, dt)
    pos = np.zeros((n, 3))
    pos[:, 0] = 0.1 * np.arange(n) * dt
    pos[:, 2] = 0.15
    up = np.ones(n)
    m = E.screen_metrics(pos, up, sch, dt, CFG["criteria"])
    assert m["passed"] == 1 and m["speed"] == pytest.approx(0.1)
    k = PR.n_steps(3.0, dt)
    pos2 = pos.copy()
    pos2[k:, 2] = 0.05
    m = E.screen_metrics(pos2, up, sch, dt, CFG["criteria"])
    assert m["passed"] == 0 and m["fallen"] == 1 and m["up_seconds"] == pytest.approx(
        3.0 - 0.5, abs=dt)
