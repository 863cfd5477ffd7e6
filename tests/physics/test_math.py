"""math.py: eq. 7.1 re-orthonormalisation, safe norms, bases and small inverses."""

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.math import (decay_gradient, inv3, inv_spd, orthonormalize, quat_to_rot,
                                 safe_norm, safe_normalize, tangent_basis)


def test_orthonormalize_contracts_error_quadratically():
    rng = np.random.default_rng(0)
    r = quat_to_rot(rng.normal(size=4))
    a = r + 1e-2 * rng.normal(size=(3, 3))
    e0 = np.abs(a.T @ a - np.eye(3)).max()
    b = np.asarray(orthonormalize(jnp.asarray(a), 1))
    e1 = np.abs(b.T @ b - np.eye(3)).max()
    assert e1 < 5 * e0 ** 2  # Newton-Schulz: quadratic convergence
    assert np.abs(b - r).max() < 2e-2


def test_safe_norm_gradient_finite_at_zero():
    g = jax.grad(lambda x: safe_norm(x))(jnp.zeros(3))
    assert np.all(np.isfinite(g)) and np.all(g == 0)
    g2 = jax.grad(lambda x: safe_norm(x))(jnp.asarray([3.0, 4.0, 0.0]))
    np.testing.assert_allclose(g2, [0.6, 0.8, 0.0], rtol=1e-6)
    g3 = jax.grad(lambda x: safe_normalize(x)[0])(jnp.zeros(3))
    assert np.all(np.isfinite(g3))


def test_tangent_basis_orthonormal():
    rng = np.random.default_rng(1)
    n = rng.normal(size=(64, 3))
    n[0] = [0, 0, -1]
    n[1] = [0, 0, 1]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    t1, t2 = (np.asarray(t) for t in tangent_basis(jnp.asarray(n)))
    for a, b in ((t1, t2), (t1, n), (t2, n)):
        np.testing.assert_allclose(np.sum(a * b, 1), 0, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(t1, axis=1), 1, atol=1e-6)
    np.testing.assert_allclose(np.cross(t1, t2), n, atol=1e-5)


def test_small_inverses_match_numpy():
    rng = np.random.default_rng(2)
    x = rng.normal(size=(5, 6, 6))
    spd = x @ np.swapaxes(x, 1, 2) + 0.5 * np.eye(6)
    np.testing.assert_allclose(inv_spd(jnp.asarray(spd)), np.linalg.inv(spd), rtol=2e-3, atol=1e-4)
    # robots-last layout: matrices on axes 1, 2 of (joints, 6, 6, robots)
    last = np.moveaxis(spd.reshape(5, 1, 6, 6), 0, -1)
    inv_last = np.asarray(inv_spd(jnp.asarray(last), axis=1))
    assert inv_last.shape == (1, 6, 6, 5)
    np.testing.assert_allclose(np.moveaxis(inv_last, -1, 0)[:, 0], np.linalg.inv(spd), rtol=2e-3,
                               atol=1e-4)
    a = rng.normal(size=(5, 3, 3)) + 3 * np.eye(3)
    np.testing.assert_allclose(inv3(jnp.asarray(a)), np.linalg.inv(a), rtol=1e-4, atol=1e-5)


def test_decay_gradient_is_identity_forward():
    x = {"a": jnp.array([1.0, -2.0, 3.0]), "n": jnp.array([1, 2])}
    y = decay_gradient(x, 0.3)
    np.testing.assert_array_equal(np.asarray(y["a"]), np.asarray(x["a"]))
    np.testing.assert_array_equal(np.asarray(y["n"]), np.asarray(x["n"]))


def test_decay_gradient_scales_the_backward_pass():
    x = jnp.array([1.0, -2.0, 3.0])
    g = jax.grad(lambda v: jnp.sum(decay_gradient(v, 0.3) ** 2))(x)
    np.testing.assert_allclose(np.asarray(g), 0.3 * 2 * np.asarray(x), rtol=1e-6)


def test_decay_gradient_compounds_per_step_like_alpha_to_the_k():
    # a scan of k steps, the state decayed after every step: d x_k / d x_0 = alpha^k
    alpha, k = 0.9, 7

    def run(x0):
        def body(x, _):
            return decay_gradient(1.0 * x, alpha), None
        xk, _ = jax.lax.scan(body, x0, None, length=k)
        return xk

    assert float(run(jnp.float32(2.0))) == 2.0
    np.testing.assert_allclose(float(jax.grad(run)(jnp.float32(2.0))), alpha ** k, rtol=1e-6)
