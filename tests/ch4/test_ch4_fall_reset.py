"""The treadmill assistant of chapter 4 (departure ch4.fall_reset): a robot that is down
when its window begins, having entered from another gait, is set back on its feet at its
start pose, eases into the gait under test again, and the reset is counted; a robot
that is up, or that entered from its own gait, is left alone bit for bit."""

from __future__ import annotations

import functools
import logging

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.config import load_config
from thesis.gaits import conditions as C
from thesis.gaits import runner as R
from thesis.ch4 import transfer_runs as TR
from thesis.runctx import RunContext
from thesis.store import check_result

FALL_HEIGHT = 0.08  # [m], the profiles' fall criterion
#: A fall height above the standing robot: every robot is down at every instant.
ALWAYS_DOWN = 1.0


@pytest.fixture(scope="module")
def oncilla():
    cfg = load_config("smoke")["ch4"]
    model, state = C.condition_model(cfg, "flat")
    return model, state


def _leaves_equal(a, b) -> bool:
    """Every leaf of two states equal bit for bit (and of the same dtype)."""
    la, lb = jax.tree.leaves(a), jax.tree.leaves(b)
    return len(la) == len(lb) and all(
        np.asarray(x).dtype == np.asarray(y).dtype and np.array_equal(x, y)
        for x, y in zip(la, lb))


def _on_its_side(model, state, t: float):
    """``state`` turned 90 degrees about the trunk's x axis (lying on its side), moving,
    at time ``t`` [s]."""
    trunk = R.O.trunk_index(model)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]], np.float32)
    pos = np.asarray(state.pos)
    centre = pos[trunk] * np.array([1.0, 1.0, 0.0], np.float32)
    shift = np.array([0.4, 0.1, 0.0], np.float32)
    return state.replace(pos=jnp.asarray((pos - centre) @ rx.T + centre + shift),
                         rot=jnp.asarray(np.einsum("ij,bjk->bik", rx, state.rot)),
                         vel=state.vel + 0.3, time=jnp.asarray(t, state.time.dtype))


def _walking(state, t: float):
    """``state`` moved forward and moving, upright, at time ``t`` [s]."""
    return state.replace(pos=state.pos + jnp.asarray([0.4, 0.0, 0.0], state.pos.dtype),
                         vel=state.vel + 0.3, time=jnp.asarray(t, state.time.dtype))


def test_a_robot_down_is_set_back_at_its_start_pose_keeping_the_clock(oncilla):
    model, start = oncilla
    down = _on_its_side(model, start, 0.75)
    assert bool(R.is_down(model, down, FALL_HEIGHT))
    after, reset = R.assist(model, down, start, FALL_HEIGHT, jnp.asarray(True))
    assert bool(reset)
    assert _leaves_equal(after, start.replace(time=down.time))


def test_a_robot_up_or_entered_from_its_own_gait_is_not_touched(oncilla):
    model, start = oncilla
    up = _walking(start, 0.75)
    assert not bool(R.is_down(model, up, FALL_HEIGHT))
    after, reset = R.assist(model, up, start, FALL_HEIGHT, jnp.asarray(True))
    assert not bool(reset) and _leaves_equal(after, up)
    down = _on_its_side(model, start, 0.75)  # down, but not eligible
    after, reset = R.assist(model, down, start, FALL_HEIGHT, jnp.asarray(False))
    assert not bool(reset) and _leaves_equal(after, down)


def test_assist_is_branch_free_under_jit_and_vmap(oncilla):
    model, start = oncilla
    batch = jax.tree.map(lambda *x: jnp.stack(x), _walking(start, 0.75),
                         _on_its_side(model, start, 0.75), _on_its_side(model, start, 0.75))
    starts = R.batch_states(start, 3)
    check = jax.jit(jax.vmap(functools.partial(R.assist, model, fall_height=FALL_HEIGHT)))
    after, reset = check(batch, starts, eligible=jnp.asarray([True, True, False]))
    assert list(np.asarray(reset)) == [False, True, False]
    row = lambda tree, i: jax.tree.map(lambda x: x[i], tree)  # noqa: E731
    assert _leaves_equal(row(after, 0), row(batch, 0))
    assert _leaves_equal(row(after, 1), start.replace(time=row(batch, 1).time))
    assert _leaves_equal(row(after, 2), row(batch, 2))


def test_restart_commands_ease_into_the_gait_under_test_again():
    fam = TR.FAMILY
    p = jnp.asarray(0.5 * (fam.lower + fam.upper), jnp.float32)
    cmd = jnp.arange(12, dtype=jnp.float32)
    t0, settle = jnp.float32(0.75), 0.25
    never = R.restart_commands(fam, p, t0, jnp.float32(jnp.inf), settle, 0.5, cmd)
    assert np.array_equal(never, cmd)  # left alone: the protocol's commands, bit for bit
    before = R.restart_commands(fam, p, t0 - 0.01, t0, settle, 0.5, cmd)
    assert np.array_equal(before, cmd)
    at = R.restart_commands(fam, p, t0, t0, settle, 0.5, cmd)
    np.testing.assert_allclose(at, R.O.build_offsets(), atol=1e-6)  # its start pose
    eased = R.restart_commands(fam, p, t0 + settle, t0, settle, 0.5, cmd)
    np.testing.assert_allclose(eased, fam.commands_at_phase(p, jnp.float32(0.0)), atol=1e-5)


@pytest.mark.slow
def test_simulate_sets_back_only_eligible_robots_down_at_the_check(oncilla):
    """Every robot is down (ALWAYS_DOWN); only the eligible ones are set back, and only
    from the check on; the others run exactly as without the check's resets."""
    model, state = oncilla
    fam = TR.FAMILY
    rng = np.random.default_rng(0)
    p = fam.project(rng.uniform(fam.lower, fam.upper, (3, 12))).astype(np.float32)
    mem = dict(p_from=np.roll(p, 1, axis=0), p_to=p)
    fn = R.gait_command_fn(fam, 0.1, 0.1)
    run = functools.partial(R.simulate, model, state, fn, mem, 0.5, chunk=None, reset_at=0.2,
                            fall_height=ALWAYS_DOWN)
    sim = run(may_reset=[True, False, True])
    ref = run(may_reset=[False, False, False])
    assert list(sim["reset"]) == [True, False, True] and not ref["reset"].any()
    k = int(np.argmin(np.abs(sim["t"] - 0.2)))  # the sample at the check, before it
    np.testing.assert_array_equal(sim["pos"][:, :k + 1], ref["pos"][:, :k + 1])
    np.testing.assert_array_equal(sim["pos"][1], ref["pos"][1])
    np.testing.assert_array_equal(sim["rot"][1], ref["rot"][1])
    trunk = R.O.trunk_index(model)
    start = np.asarray(state.pos)[trunk]
    for i in (0, 2):  # one command period after the reset: standing at the start pose
        np.testing.assert_allclose(sim["pos"][i, k + 1, trunk], start, atol=0.01)
        assert sim["rot"][i, k + 1, trunk, 2, 2] > 0.99
    assert not R.exploded(model, sim).any()  # the jump back is not a speed


def test_window_starts_later_for_a_robot_set_back():
    cfg = {"protocol": {"settle": 0.25, "transition_seconds": 0.5, "run_seconds": 1.0}}
    np.testing.assert_allclose(TR.window_starts(cfg, [True, False]), [1.0, 0.75])


TINY = {"ch4": {
    "seeds": [0, 1],
    "protocol": {"settle": 0.1, "transition_seconds": 0.1, "run_seconds": 0.3,
                 "fall_height": ALWAYS_DOWN},
    "pso": {"particles": 3, "generations": 2},
    "reeval": {"repeats": 1},
}}


@pytest.mark.slow
def test_flat_run_counts_the_resets_per_generation(tmp_path):
    """With every robot down, every evaluation entered from another gait is set back
    (the run's first particle entered from its own gait) and still falls in its window."""
    cfg = load_config("smoke", overrides=TINY)
    ctx = RunContext(key="ch4/flat", profile="smoke", config=cfg["ch4"], full_config=cfg,
                     inputs={}, output=tmp_path / "x.nc", log=logging.getLogger("test"))
    with jax.numpy_dtype_promotion("standard"), jax.numpy_rank_promotion("allow"):
        ds = TR.flat(ctx)
    check_result(ds)
    assert ds["reset"].dims == ("seed", "generation", "particle")
    assert ds["reset_count"].dims == ("seed", "generation")
    assert ds["reset_count"].attrs["units"] == "1" and ds["reset_count"].attrs["long_name"]
    np.testing.assert_array_equal(ds["reset_count"].values, [[2, 3], [2, 3]])
    np.testing.assert_array_equal(ds["reset"].values[:, 0, 0], 0.0)
    np.testing.assert_array_equal(ds["reset_count"].values, ds["reset"].sum("particle"))
    assert (ds["fallen"].values == 1).all()  # down in its own window too: still a fall
