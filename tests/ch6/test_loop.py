"""The closed loop on the simulated Oncilla: encoders, NaN handling, open-loop tracking."""

from __future__ import annotations

import importlib

import jax
import numpy as np
import pytest

from thesis.ch6 import controller as C
from thesis.ch6 import loop
from thesis.ch6 import protocol as PR
from thesis.ch6 import teacher as TE
from thesis.errors import SimulationDiverged

O = importlib.import_module("thesis.physics.models.oncilla")

DT, SUB = 0.00205, 4
STEP = 2 * np.pi / 4096  # one count of the 12-bit encoders [rad]
SCH = PR.Schedule(settle=0.2, normalisation=0.2, stage1=0.1, stage2=0.1, running=0.1,
                  off=0.05, recovery=0.05)
N = PR.n_steps(SCH.total, DT * SUB)


@pytest.fixture(scope="module")
def robot():
    return O.oncilla(dt=DT)


@pytest.fixture(scope="module")
def table():
    fam = TE.family("half_ellipse")
    p = np.array([140.0, 5.0, -10.0, 40.0, 20.0, 25.0, 0.55, 1.7])  # Tab. 3.1a order
    return TE.command_table(fam, p, N, DT * SUB, SCH.settle)


def _run(teacher, seed):
    wh, wb = C.draw_hidden(np.random.default_rng(seed), 6)
    return dict(teacher=teacher, **PR.signals(SCH, DT * SUB, N), w_hidden=wh, w_bias=wb,
                hidden_mask=np.ones(6), slot_mask=np.ones(3), identity=False,
                noise_std=0.01, noise_seed=seed, perturb=0.0, perturb_seed=seed,
                jitter=0.15, encoder_noise=0.5 * STEP, encoder_resolution=STEP,
                sensing_seed=seed)


def test_perturbed_twin_starts_at_the_rounding_level(robot):
    """A twin's initial positions differ at 1e-7 relative (per coordinate, seeded); a zero
    perturbation returns the state bit for bit."""
    _, state = robot
    same = loop.perturbed(state, 0.0, 3)
    np.testing.assert_array_equal(np.asarray(same.pos), np.asarray(state.pos))
    twin = loop.perturbed(state, 1e-7, 3)
    pos = np.asarray(state.pos)
    rel = np.abs(np.asarray(twin.pos)[pos != 0] / pos[pos != 0] - 1.0)
    assert 0 < rel.max() < 1e-6 and np.mean(rel > 0) > 0.3  # most move by an ulp or more
    again = loop.perturbed(state, 1e-7, 3)
    np.testing.assert_array_equal(np.asarray(again.pos), np.asarray(twin.pos))
    other = loop.perturbed(state, 1e-7, 4)
    assert not np.array_equal(np.asarray(other.pos), np.asarray(twin.pos))


def test_encoders_are_hip_and_knee_in_thesis_angles(robot):
    model, state = robot
    dofs = loop.encoder_dofs(model)
    assert len(set(dofs.tolist())) == 8
    q = np.asarray(jax.jit(lambda s: loop.all_sensors(model, s)["joint_angle"])(state))[dofs]
    np.testing.assert_allclose(q + loop.encoder_offsets(), np.asarray(O.build_offsets())[
        list(loop.HIP_KNEE)], atol=1e-4)  # standing in the build pose
    assert [O.SERVO_NAMES[i] for i in loop.HIP_KNEE][:2] == ["LF_hip", "LF_knee"]


def test_nan_stops_with_condition_seed_and_step(robot, table):
    model, state = robot
    bad = table.copy()
    k = PR.n_steps(SCH.bounds()["stage1"][0], DT * SUB) + 5  # RLS learns at step k
    bad[k] = np.nan  # a NaN target makes W NaN: the output is NaN from step k + 1
    with pytest.raises(SimulationDiverged) as err:
        loop.simulate(model, state, [_run(table, 0), _run(bad, 1)], SUB,
                      experiment="ch6/test", labels=[("ok", 0), ("broken", 1)])
    e = err.value
    assert e.experiment == "ch6/test/broken" and e.seed == 1 and e.step == k + 1
    assert "seed=1" in str(e) and f"step={k + 1}" in str(e)


def test_open_loop_teacher_moves_the_joints_it_commands(robot, table):
    model, state = robot
    runs = [_run(table, 0), _run(table, 1)]
    runs[1]["share"] = np.ones(N, np.float32)  # open loop: the teacher drives throughout
    runs[1]["learn"] = np.zeros(N, np.float32)
    rec, timing = loop.simulate(model, state, runs, SUB, experiment="ch6/test",
                                labels=[("a", 0), ("b", 1)])
    assert rec["y_hat"].shape == (2, N, 12) and rec["encoders"].shape == (2, N, 8)
    assert timing["rollout_seconds"] > 0
    hip = loop.HIP_KNEE[::2]
    enc = rec["encoders"][1, :, ::2]
    cmd = table[:, list(hip)]
    k = PR.n_steps(SCH.settle, DT * SUB)
    lag = 3  # the servo follows a few controller steps behind
    err = np.abs(enc[k + lag:] - cmd[k:-lag]).mean()
    assert err < 0.1 and np.ptp(cmd[k:], axis=0).max() > 0.1
    # the open-loop run never learned: its output stays 0; the other learned something
    np.testing.assert_array_equal(rec["y_hat"][1], 0.0)
    assert np.abs(rec["y_hat"][0]).max() > 0.01
    assert np.all(rec["trunk_up"] > 0.9)


def test_encoders_read_whole_counts_with_read_noise():
    """Readings are whole counts; the read noise moves about half the readings of a
    constant angle at half a count, none at zero noise; resolution 0 reads exactly."""
    q = np.full((8,), 0.3 + 0.25 * STEP, np.float32)
    keys = [jax.random.key(i) for i in range(200)]
    quiet = np.array([loop.read_encoders(q, k, 0.0, STEP) for k in keys])
    noisy = np.array([loop.read_encoders(q, k, 0.5 * STEP, STEP) for k in keys])
    np.testing.assert_allclose(quiet / STEP, np.round(quiet / STEP), atol=1e-3)
    np.testing.assert_allclose(noisy / STEP, np.round(noisy / STEP), atol=1e-3)
    assert np.all(quiet == quiet[0])
    moved = np.mean(noisy != quiet[0])
    assert 0.2 < moved < 0.8
    np.testing.assert_array_equal(loop.read_encoders(q, keys[0], 0.0, 0.0), q)


def test_period_jitter_changes_the_trajectory(robot, table):
    """The jittered controller period (each step's physics time step scaled by 1 + jitter
    u) changes an open-loop run; without jitter two identical runs agree bit for bit."""
    model, state = robot
    fixed = {**_run(table, 0), "jitter": 0.0}
    runs = [_run(table, 0), fixed, fixed]
    rec, _ = loop.simulate(model, state, runs, SUB, experiment="test_jitter",
                           labels=[("jitter", 0), ("fixed", 0), ("fixed", 0)])
    x = np.asarray(rec["trunk_pos"])
    assert np.all(np.isfinite(x))
    np.testing.assert_array_equal(x[1], x[2])
    assert np.max(np.abs(x[0] - x[1])) > 1e-4
