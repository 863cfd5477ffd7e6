"""The joint arm's negative control (:func:`thesis.coopt.experiments.random_direction_steps`):
updates along random directions with the gradient runs' optimisers, so every step has
their size and none knows the objective."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.coopt.experiments import random_direction_steps
from thesis.ch7 import bptt


def _run(seed: int, lr: float = 0.01, steps: int = 5):
    net = {"w": jnp.zeros((3, 4), jnp.float32), "b": jnp.zeros(4, jnp.float32)}
    u = jnp.zeros(8, jnp.float32)
    keys = jax.random.split(jax.random.key(seed), steps)
    opt = bptt.make_optimizer(lr, 1.0)
    return random_direction_steps(net, u, keys, opt, bptt.make_optimizer(lr, 1.0))


def test_random_directions_take_the_optimisers_step_size():
    """Adam moves every coordinate by about its learning rate per update whatever the
    direction's scale: after 5 updates at 0.01 each coordinate moved, by at most 0.05."""
    net, u = _run(0)
    moved = np.abs(np.concatenate([np.ravel(net["w"]), np.ravel(net["b"]), np.ravel(u)]))
    assert (moved > 0).all() and (moved <= 5 * 0.01 * (1 + 1e-3)).all()
    # a random direction: both signs, and not the same move for every coordinate
    assert (np.ravel(net["w"]) > 0).any() and (np.ravel(net["w"]) < 0).any()


def test_the_control_is_seeded_by_its_keys():
    a, b, c = _run(0), _run(0), _run(1)
    np.testing.assert_array_equal(np.asarray(a[1]), np.asarray(b[1]))
    assert not np.array_equal(np.asarray(a[1]), np.asarray(c[1]))
