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
