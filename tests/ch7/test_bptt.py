"""BPTT tricks of §7.3.2: gradient decay wrapper, clipping optimiser, divergence checks."""

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest

from thesis.ch7 import bptt
from thesis.errors import SimulationDiverged


def _two_updates(opt, grads):
    params = jnp.zeros(2)
    st = opt.init(params)
    out = []
    for g in grads:
        u, st = opt.update(g, st, params)
        out.append(np.asarray(u))
    return out


def test_optimizer_clips_the_gradient_norm_before_adam():
    grads = [jnp.array([30.0, 40.0]), jnp.array([0.3, 0.4])]  # norms 50 and 0.5
    with jax.numpy_dtype_promotion("standard"):  # optax's bias correction mixes int/float
        got = _two_updates(bptt.make_optimizer(0.1, 1.0), grads)
        clipped = [grads[0] / 50.0, grads[1]]
        want = _two_updates(optax.adam(0.1), clipped)
        unclipped = _two_updates(optax.adam(0.1), grads)
    np.testing.assert_allclose(got[1], want[1], rtol=1e-5)
    assert not np.allclose(got[1], unclipped[1], rtol=1e-3)


def test_check_finite_raises_simulation_diverged():
    bptt.check_finite({"a": jnp.ones(3)}, "ch7/x", 1, 2, "loss")
    with pytest.raises(SimulationDiverged, match="seed=4 step=7"):
        bptt.check_finite({"a": jnp.array([1.0, jnp.nan])}, "ch7/x", 4, 7, "loss")


def test_first_reach_counts_from_one_and_flags_misses():
    assert bptt.first_reach([0.5, 0.2, 0.05, 0.01], 0.1) == (3.0, True)
    n, ok = bptt.first_reach([0.5, 0.2], 0.1)
    assert np.isnan(n) and not ok
