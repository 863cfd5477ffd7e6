"""The Oncilla's model-level checks (thesis.modelcheck.checks, ``thesis bench oncilla``):
the measuring machinery, on synthetic inputs where the answer is known and on short
simulations of the current model. No test here asserts an outcome a model revision is
meant to bring (a fall rate, an encoder R^2); one checks what the model is built to be
(drives that yield under load)."""

from __future__ import annotations

import importlib
import logging
from types import SimpleNamespace

import numpy as np
import pytest

from thesis import registry
from thesis.config import load_config
from thesis.ch6 import loop
from thesis.gaits import conditions as C
from thesis.modelcheck import bench as B
from thesis.modelcheck import checks as M
from thesis.gaits import runner as R

O = importlib.import_module("thesis.physics.models.oncilla")


def test_r_squared_is_one_for_a_signal_made_of_the_forces_and_zero_for_noise():
    rng = np.random.default_rng(0)
    F = rng.normal(size=(2000, 12))
    y = F @ rng.normal(size=12) + 0.3
    assert M.r_squared(y, F) > 1 - 1e-9
    noise = rng.normal(size=(2000, 3))
    r2 = M.r_squared(noise, F)
    assert r2.shape == (3,) and np.all(np.abs(r2) < 0.02)
    half = M.r_squared(F[:, 0] + rng.normal(size=2000), F)  # half the variance
    assert 0.45 < half < 0.55
    assert np.isnan(M.r_squared(np.full(2000, 2.0), F))  # a constant has no variance
    assert np.isnan(M.r_squared(y[:10], F[:10]))  # fewer samples than regressors


def test_phase_residual_keeps_only_the_cycle_to_cycle_part():
    rng = np.random.default_rng(1)
    phase = np.arange(4000) * 0.0173
    wobble = 0.05 * rng.normal(size=4000)
    x = np.sin(2 * np.pi * phase) + wobble
    res = M.phase_residual(x, phase)
    assert np.std(res - wobble) < 0.01 * np.std(x)
    F = np.column_stack([np.cos(2 * np.pi * phase), wobble])  # periodic + the wobble
    assert M.r_squared(M.phase_residual(x, phase), M.phase_residual(F, phase)) > 0.9
    assert M.r_squared(M.phase_residual(x, phase),
                       M.phase_residual(F[:, :1], phase)) < 0.05


def test_fall_rate_binning_counts_each_run_once():
    values = np.array([0.0, 0.5, 0.99, 1.0, 1.5, 2.0, 2.5, -0.1])
    fallen = np.array([1, 0, 1, 1, 1, 0, 1, 1], bool)
    b = M.fall_rate_bins(values, fallen, [0.0, 1.0, 2.0])
    np.testing.assert_array_equal(b["n"], [3, 3])  # 2.0 in the last bin; 2.5, -0.1 outside
    np.testing.assert_array_equal(b["falls"], [2, 2])
    np.testing.assert_allclose(b["rate"], [2 / 3, 2 / 3])
    np.testing.assert_allclose(b["centre"], [0.5, 1.5])
    empty = M.fall_rate_bins([0.2], [True], [0.0, 1.0, 2.0])
    assert empty["rate"][0] == 1.0 and np.isnan(empty["rate"][1])


def test_encoder_readout_is_chapter_6s():
    model, _ = O.oncilla()
    assert M.ENCODERS == loop.ENCODERS
    np.testing.assert_array_equal(M.encoder_dofs(model), loop.encoder_dofs(model))
    np.testing.assert_array_equal(M.encoder_offsets(), loop.encoder_offsets())
    assert M.ENCODER_COMMANDS == loop.HIP_KNEE


def test_random_gaits_cover_tab_4_1_and_are_reproducible():
    fam = M.FAMILY
    p = M.sample_gaits(np.random.default_rng(3), 400)
    np.testing.assert_array_equal(p, M.sample_gaits(np.random.default_rng(3), 400))
    np.testing.assert_allclose(fam.project(p), p)  # every draw feasible
    x0, a, f = (p[:, fam.index(n)] for n in ("x0", "a", "f"))
    assert x0.min() < 130 and x0.max() > 154 and f.min() < 1.55 and f.max() > 1.95
    frac = a / fam.table.a_max(x0)
    assert frac.min() < 0.05 and frac.max() > 0.95
    assert abs(np.mean(frac > 0.99) - 0.01) < 0.02  # uniform in a, not piled on a_max
    nominal = M.nominal_gait()
    np.testing.assert_allclose(fam.project(nominal), nominal)
    assert nominal[fam.index("f")] == pytest.approx(1.75)


@pytest.fixture(scope="module")
def pushed():
    """One standing robot, pushed sideways by 0 and by 20 N s, and one unpushed; 1 s."""
    cfg = load_config("smoke")["ch4"]
    model, state = C.base_model(cfg)
    model = C.untethered(model)
    m_trunk = float(np.asarray(model.body_mass)[O.trunk_index(model)])
    kick = np.zeros((3, 3))
    kick[2, 1] = 20.0 / m_trunk
    runs = dict(p=np.tile(M.nominal_gait(), (3, 1)), stand=np.ones(3), kick=kick,
                kick_time=np.array([np.inf, 0.3, 0.3]))
    sim = M.simulate_runs(model, state, runs, duration=1.0, settle=0.25, t_transition=0.5,
                          batch=3)
    return model, state, sim


def test_model_check_runs_start_from_the_perturbed_state_of_a_twin_run(pushed):
    """The model checks' runs are perturbed twins under ``thesis --perturb`` like every
    rollout (the pipeline's perturbed twin of results/<profile>/model/ measures their
    sensitivity): the same runs differ under a rounding-level perturbation, and are bit
    for bit the unperturbed ones again once it is off."""
    from thesis.physics import perturbation

    model, state, sim = pushed
    runs = dict(p=M.nominal_gait()[None], stand=np.zeros(1), kick=np.zeros((1, 3)),
                kick_time=np.array([np.inf]))
    kw = dict(duration=0.5, settle=0.25, t_transition=0.5, batch=1)
    plain = M.simulate_runs(model, state, runs, **kw)
    with perturbation.scope(1e-7):
        twin = M.simulate_runs(model, state, runs, **kw)
    again = M.simulate_runs(model, state, runs, **kw)
    assert not np.array_equal(plain["pos"], twin["pos"])
    np.testing.assert_allclose(plain["pos"], twin["pos"], atol=1e-3)  # a twin, not a new run
    assert np.array_equal(plain["pos"], again["pos"])


def test_standing_height_is_the_kinematic_nominal(pushed):
    model, state, sim = pushed
    st = M.standing(model, state, sim, 0)
    # the knee springs give a little under the weight (oncilla.py: about 1 cm)
    assert abs(st["trunk_height"] - st["nominal_trunk_height"]) < 0.02
    assert abs(st["com_height"] - st["nominal_com_height"]) < 0.02
    np.testing.assert_allclose(st["toe"], st["nominal_toe"], atol=0.015)
    assert st["trunk_tilt"] < 0.05
    # the toes rest on the floor: trunk height = toe depth + toe radius - hip offset
    depth = -st["toe"][:, 2].mean()
    assert st["trunk_height"] == pytest.approx(depth + O.TOE_RADIUS - O.HIPS[0][2], abs=0.004)


def test_toe_forces_carry_the_standing_robot(pushed):
    model, _, sim = pushed
    weight = float(np.asarray(model.body_mass).sum()) * 9.81
    f = sim["force"][0, -10:].astype(np.float64)  # last 0.1 s standing
    assert f[..., 2].sum(-1).mean() == pytest.approx(weight, rel=0.05)
    assert np.abs(f[..., :2].sum(-2)).max() < 0.05 * weight  # no net sideways load
    assert np.all(f[..., 2] > 0.1 * weight / 4)  # on all four feet


def test_a_push_of_zero_never_falls_and_a_huge_one_does(pushed):
    model, _, sim = pushed
    terms = R.speed_terms(model, sim, 0.3, 0.08)
    assert terms["fallen"].tolist() == [False, False, True]
    kind = M.fall_kind(model, sim, 0.08)
    assert [M.FALL_KINDS[k] for k in kind[:2]] == ["none", "none"]
    assert M.FALL_KINDS[kind[2]] in ("roll", "low")
    np.testing.assert_array_equal(sim["q"][0], sim["q"][1])  # a zero kick changes nothing
    mask = M.upright_mask(model, sim, 0.08, 0.3)
    assert mask[0, 30:].all() and not mask[0, :30].any() and not mask[2, -1]


def test_bench_writes_its_dataset_at_smoke_sizes():
    assert registry.BENCHMARKS["oncilla"] == "model/oncilla"
    assert registry.resolve("model/oncilla") is B.oncilla
    config = load_config("smoke")
    ctx = SimpleNamespace(full_config=config, root_seed=int(config["root_seed"]),
                          key="model/oncilla", log=logging.getLogger("test"))
    ds = B.oncilla(ctx)
    cfg = config["physics"]["oncilla_model"]
    n = int(cfg["gaits"])
    assert ds.sizes["gait"] == n and ds.sizes["joint"] == 8
    assert ds.attrs["model_label"] == "current" and len(ds.attrs["model_code_sha256"]) == 64
    for name in ("stand_trunk_height", "fall_rate", "roll_fall_rate", "fall_rate_by_a",
                 "fall_rate_by_x0", "fall_rate_by_f", "push_fallen", "push_max_tilt",
                 "encoder_r2_forces_nominal", "encoder_r2_command_nominal",
                 "encoder_r2_forces_given_command_mean", "encoder_r2_forces_beyond_phase_mean"):
        assert name in ds and "units" in ds[name].attrs, name
    assert int(ds["gaits_by_a"].sum()) == n and int(ds["gaits_by_f"].sum()) == n
    assert int(ds["falls_by_x0"].sum()) == int(ds["fallen"].sum())
    assert float(ds["fall_rate"]) == pytest.approx(float(ds["fallen"].mean()))
    push = ds["push_fallen"].sel(posture="standing")
    assert int(push.sel(push=0.0)) == 0 and int(push.sel(push=20.0)) == 1
    r2 = ds["encoder_r2_forces_nominal"].values
    assert np.all(np.isfinite(r2)) and np.all((r2 >= 0) & (r2 <= 1))
    # the same gaits whatever the model: the draw depends on the root seed only
    runs, _ = B.plan_runs(cfg, ctx.root_seed, 4.0, 0.25)
    np.testing.assert_allclose(ds["gait_params"].values, runs["p"][-n:])


def test_motor_encoders_feel_the_load_on_the_legs():
    """The hip and knee drives are compliant (oncilla.py "Drives"): on the standing robot
    the weight deflects the encoders' motor angles from the commanded build pose by many
    counts of a 12-bit encoder (load / stiffness), while the same robot with gravity
    switched off holds its commands to within a count."""
    import jax
    import jax.numpy as jnp

    from thesis.physics import sensors, step
    model, state = O.oncilla()
    dofs, count = loop.encoder_dofs(model), 2 * np.pi / 4096
    action = jnp.zeros((model.n_servo,), state.pos.dtype)  # the build pose

    def deflection(m):
        run = jax.jit(lambda s: jax.lax.scan(lambda s, _: (step(m, s, action), None), s, None,
                                              length=400)[0])
        return np.abs(np.asarray(sensors(m, run(state))["joint_angle"])[dofs])

    loaded = deflection(model)
    weightless = deflection(model.replace(gravity=jnp.zeros_like(model.gravity)))
    assert weightless.max() < count
    assert np.median(loaded) > 5 * count
