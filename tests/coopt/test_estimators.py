"""REINFORCE and ES estimates (thesis.coopt.estimators) against known gradients.

* The prefix-sum bookkeeping gives exactly the estimate computed directly from the block's
  samples (REINFORCE with its leave-one-out baseline, antithetic ES).
* On a smooth function with a known gradient both estimators converge (cosine -> 1 with
  more rollouts), and a single-rollout estimate does not (the test can fail).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.coopt import estimators as est

D = 6
A = np.array([1.0, -2.0, 0.5, 3.0, 0.0, -1.0])


def _returns(th):
    """(C, d) -> (C,): a linear function plus a small curvature and a constant offset."""
    a = jnp.asarray(A, th.dtype)
    return th @ a + 0.1 * jnp.sum(th * th, axis=1) + 5.0


def test_log_grid():
    assert est.log_grid(200).tolist() == [1, 2, 5, 10, 20, 50, 100, 200]
    assert est.log_grid(10000)[-1] == 10000 and est.log_grid(10000)[0] == 1


def test_block_estimates_equal_direct_computation():
    theta = jnp.zeros((D,), jnp.float32)
    sigma, n, chunk, repeats = 0.1, 40, 8, 3
    counts = [1, 2, 5, 10, 20, 40]
    edges = np.union1d(est.boundaries(counts, n, repeats, 1),
                       est.boundaries(counts, n, repeats, 2))
    key = jax.random.PRNGKey(3)
    sums = est.stream_sums(_returns, theta, sigma, key, n, chunk, edges)
    rf, es = est.block_estimates(sums, edges, counts, n, repeats, sigma)
    eps = np.concatenate([np.asarray(jax.random.normal(jax.random.fold_in(key, c), (chunk, D)))
                          for c in range(n // chunk)])
    fp = np.asarray(_returns(jnp.asarray(sigma * eps, jnp.float32)))
    fm = np.asarray(_returns(jnp.asarray(-sigma * eps, jnp.float32)))
    np.testing.assert_allclose(sums["f_plus"], fp, rtol=1e-6)
    for m in (5, 10):
        for k in range(min(repeats, n // m)):
            sl = slice(k * m, (k + 1) * m)
            f, e = fp[sl], eps[sl]
            base = (f.sum() - f) / (m - 1)
            want = ((f - base)[:, None] * e).mean(0) / sigma
            np.testing.assert_allclose(rf[m][k], want, rtol=1e-4, atol=1e-4)
        pairs = m // 2
        for k in range(min(repeats, n // pairs)):
            sl = slice(k * pairs, (k + 1) * pairs)
            want = ((fp[sl] - fm[sl])[:, None] * eps[sl]).mean(0) / (2 * sigma)
            np.testing.assert_allclose(es[m][k], want, rtol=1e-4, atol=1e-4)
    assert 1 in rf and 1 not in es  # ES needs a pair


@pytest.mark.parametrize("which", [0, 1])
def test_estimators_converge_to_the_gradient(which):
    theta = jnp.zeros((D,), jnp.float32)
    truth = A  # gradient at 0 (the curvature term's gradient vanishes there)
    sigma, n, chunk, repeats = 0.05, 4000, 500, 4
    counts = est.log_grid(n)
    edges = np.union1d(est.boundaries(counts, n, repeats, 1),
                       est.boundaries(counts, n, repeats, 2))
    sums = est.stream_sums(_returns, theta, sigma, jax.random.PRNGKey(0), n, chunk, edges)
    blocks = est.block_estimates(sums, edges, counts, n, repeats, sigma)[which]
    med = {m: float(np.median(est.cosine(b, truth))) for m, b in blocks.items()}
    assert med[max(med)] > 0.99
    assert med[min(med)] < 0.9
    need = est.first_above(sorted(med), [med[m] for m in sorted(med)], 0.9)
    assert np.isfinite(need) and need > min(med)
    rel = est.relative_error(blocks[max(blocks)], truth)
    assert float(np.median(rel)) < 0.15


def test_first_above_needs_to_stay_above():
    assert est.first_above([1, 2, 5, 10], [0.95, 0.5, 0.92, 0.97], 0.9) == 5.0
    assert np.isnan(est.first_above([1, 2], [0.5, 0.6], 0.9))
