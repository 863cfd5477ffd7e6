"""Ball throw of §7.2.1: the BPTT gradient through the engine is finite and useful."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.diffphys import ball


@pytest.fixture(scope="module")
def short_error():
    model, state0 = ball.build({"dt": 0.01, "solver_iterations": 1})
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


def test_ball_loss_gradient_matches_float64_differences_through_landing_and_rolling(x64):
    """AD gradient of the §7.2.1 loss w.r.t. all six launch parameters equals central
    finite differences in float64 through the landing (restitution, friction impulse
    converting slip into spin) and 1.2 s of rolling: the spin-to-velocity path through
    the contact is differentiated correctly (FACTS §2.6 rows, §2.11 loss)."""
    model, state0 = ball.build({"dt": 0.01, "solver_iterations": 1})
    model, state0 = jax.tree.map(
        lambda a: a.astype(jnp.float64) if jnp.issubdtype(a.dtype, jnp.floating) else a,
        (model, state0))
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
