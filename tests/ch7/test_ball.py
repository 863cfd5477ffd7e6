"""Ball throw of §7.2.1: the BPTT gradient through the engine is finite and useful."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.ch7 import ball
from thesis.physics import rollout


@pytest.fixture(scope="module")
def short_error():
    model, state0 = ball.build({"dt": 0.01, "solver_iterations": 1, "toi_correction": False})
    return ball.errors_fn(model, state0, 40, [10.0, 0.0])


@pytest.mark.parametrize("x0", [[2.0, 0.5, 1.0, 0.0, -1.0, 0.3], [4.0, -1.0, 3.0, 1.0, 0.0, 0.0]])
def test_ball_gradient_is_finite_and_points_downhill(short_error, x0):
    f = jax.jit(lambda x: sum(short_error(x)))
    x = jnp.asarray(x0, jnp.float32)
    g = jax.grad(lambda x: sum(short_error(x)))(x)
    assert np.all(np.isfinite(np.asarray(g)))
    assert float(jnp.linalg.norm(g)) > 0
    step = 0.05 * g / jnp.linalg.norm(g)
    assert float(f(x - step)) < float(f(x))
    assert float(f(x + step)) > float(f(x))


def test_ball_gradient_matches_central_differences_in_flight(short_error):
    # 0.4 s after launch from 1.5 m upwards the ball is still in the air
    f = jax.jit(lambda x: sum(short_error(x)))
    x = jnp.asarray([2.0, 0.5, 1.0, 0.0, -1.0, 0.3], jnp.float32)
    g = np.asarray(jax.grad(lambda x: sum(short_error(x)))(x))
    eps = 1e-2
    fd = np.array([(float(f(x.at[i].add(eps))) - float(f(x.at[i].add(-eps)))) / (2 * eps)
                   for i in range(6)])
    np.testing.assert_allclose(g, fd, atol=2e-2, rtol=2e-2)


def _ball64(toi: bool):
    """(model, state0) of the §7.2.1 ball with every float leaf in float64."""
    model, state0 = ball.build({"dt": 0.01, "solver_iterations": 1, "toi_correction": toi})
    return jax.tree.map(
        lambda a: a.astype(jnp.float64) if jnp.issubdtype(a.dtype, jnp.floating) else a,
        (model, state0))


def test_ball_loss_gradient_matches_float64_differences_through_landing_and_rolling(x64):
    """AD gradient of the §7.2.1 loss w.r.t. all six launch parameters equals central
    finite differences in float64 through the landing (restitution, friction impulse
    converting slip into spin) and 1.2 s of rolling: the spin-to-velocity path through
    the contact is differentiated correctly (docs/sources.md#tpx-contact rows, §2.11 loss)."""
    model, state0 = _ball64(toi=False)
    err = ball.errors_fn(model, state0, 150, [10.0, 0.0])
    f = jax.jit(lambda x: sum(err(x)))
    # thrown down from 1.5 m: lands after ~0.3 s with backspin, then rolls
    x = jnp.asarray([3.0, -0.3, -2.0, -1.8, -1.9, 0.1], jnp.float64)
    g = np.asarray(jax.jit(jax.grad(f))(x))
    eps = 1e-6
    fd = np.array([(float(f(x.at[i].add(eps))) - float(f(x.at[i].add(-eps)))) / (2 * eps)
                   for i in range(6)])
    np.testing.assert_allclose(g, fd, rtol=1e-5, atol=1e-7)
    # the contact couples spin and travel: both the throw speed and the backspin matter
    assert abs(g[0]) > 0.1 and abs(g[4]) > 0.05


def _final_x(toi: bool, n_steps: int = 150):
    """Final horizontal position of the ball [m] as a function of (v0, w0), float64."""
    model, state0 = _ball64(toi)

    def f(x):
        s = state0.replace(vel=x[None, :3], angvel=x[None, 3:])
        final, _ = rollout(model, s, ball._no_control, None, n_steps, record=())
        return final.pos[0, 0]
    return jax.jit(f)


def test_time_of_impact_gives_the_landing_time_its_derivative(x64):
    """Thrown down from 1.5 m the ball lands after ~0.3 s and rolls. Where it is at 1.5 s
    depends on its vertical launch speed through the landing time (it flies at v_x, then
    rolls at 5/7 of it). Without the time-of-impact correction that dependence is a
    staircase (derivative exactly 0); with it the AD derivative equals the secant over
    +-0.3 m/s (several landing steps) and the flat-ground physics is unchanged."""
    x = jnp.asarray([3.0, 0.0, -2.0, 0.0, 0.0, 0.0], jnp.float64)
    secant = {}
    for toi in (False, True):
        f = _final_x(toi)
        g = np.asarray(jax.grad(f)(x))
        secant[toi] = (float(f(x.at[2].add(0.3))) - float(f(x.at[2].add(-0.3)))) / 0.6
        if toi:
            np.testing.assert_allclose(g[2], secant[toi], rtol=0.15)
            assert abs(g[2]) > 0.05
        else:
            assert g[2] == 0.0
    # both models agree on the secant (the correction does not change where balls go)
    np.testing.assert_allclose(secant[True], secant[False], rtol=0.2)


def test_time_of_impact_leaves_a_resting_ball_alone(x64):
    """A ball resting (or rolling) on the ground never approaches it faster than the
    restitution threshold, so the correction is exactly zero."""
    for v in ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]):
        model, state0 = ball.build({"dt": 0.01, "solver_iterations": 1, "toi_correction": True})
        off, _ = ball.build({"dt": 0.01, "solver_iterations": 1, "toi_correction": False})
        state0 = state0.replace(pos=state0.pos.at[0, 2].set(0.5),
                                vel=jnp.asarray([v], state0.vel.dtype))
        a, _ = rollout(model, state0, ball._no_control, None, 100, record=())
        b, _ = rollout(off, state0, ball._no_control, None, 100, record=())
        np.testing.assert_array_equal(np.asarray(a.pos), np.asarray(b.pos))
