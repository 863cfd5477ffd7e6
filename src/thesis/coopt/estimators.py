"""Score-function (REINFORCE) and antithetic evolution-strategies estimates of a gradient,
beside the engine's analytic one (thesis §8.2: "comparing those gradients to the gradient
approximations found by for instance policy gradient methods").

Both estimate the gradient of the Gaussian-smoothed objective E[f(theta + sigma eps)],
eps ~ N(0, I), from rollouts at perturbed parameters (the parameter-exploring form of
policy gradients: the noise is on the parameters, not on the actions):

* REINFORCE with n rollouts: ``(1 / n) sum_i (f_i - b_i) eps_i / sigma`` with the
  leave-one-out baseline ``b_i`` = mean of the other n - 1 returns (unbiased, the common
  variance reduction; n = 1 has no baseline);
* ES with n rollouts (n / 2 antithetic pairs): ``(1 / m) sum_i (f(theta + sigma eps_i) -
  f(theta - sigma eps_i)) eps_i / (2 sigma)``, m = n / 2.

One stream of ``n_max`` noise vectors serves every count of the log grid: the estimate
with n rollouts from block k is built from prefix sums at the block's ends
(:func:`block_estimates`), so the blocks ``[k n, (k + 1) n)`` (at most ``repeats``
of them) give the spread of the estimate at that n without more rollouts. REINFORCE's
rollouts are the pairs' positive sides, so the two estimators share the simulations.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

__all__ = ["log_grid", "boundaries", "stream_sums", "block_estimates", "cosine",
           "relative_error", "first_above"]


def log_grid(n_max: int, per_decade: int = 3) -> np.ndarray:
    """Rollout counts 1, 2, 5, 10, 20, 50, ... up to ``n_max`` (``per_decade`` = 3; 1:
    powers of ten), ``n_max`` itself included."""
    steps = {1: (1,), 2: (1, 3), 3: (1, 2, 5)}[int(per_decade)]
    out, dec = [], 1
    while dec <= n_max:
        out += [s * dec for s in steps if s * dec <= n_max]
        dec *= 10
    return np.unique(np.array(out + [int(n_max)], dtype=np.int64))


def boundaries(counts, n_total: int, repeats: int, per_sample: int = 1) -> np.ndarray:
    """Sorted sample indices where some block of some count ends or starts: for count n
    (rollouts; ``per_sample`` rollouts per noise sample) the blocks of ``n // per_sample``
    samples, at most ``repeats`` of them within ``n_total`` samples."""
    edges = {0}
    for n in counts:
        size = int(n) // per_sample
        if size < 1:
            continue
        for k in range(min(int(repeats), n_total // size) + 1):
            edges.add(k * size)
    return np.array(sorted(e for e in edges if e <= n_total), dtype=np.int64)


def stream_sums(returns_fn, theta, sigma: float, key, n_samples: int, chunk: int,
                edges: np.ndarray):
    """Prefix sums of the estimators' terms at the sample indices ``edges``.

    Args:
        returns_fn: ``(C, d) parameters -> (C,) returns`` (jitted, vmapped rollouts).
        theta: (d,) the parameters. sigma: noise standard deviation.
        key: PRNG key of the noise stream (chunk c uses ``fold_in(key, c)``).
        n_samples: noise samples (antithetic pairs: 2 rollouts each); a multiple of chunk.
        chunk: samples per call of ``returns_fn`` (its batch).
        edges: sorted sample indices (from :func:`boundaries`).
    Returns:
        dict of arrays with a leading axis over ``edges``: ``fe`` sum f+ eps (E, d),
        ``e`` sum eps (E, d), ``f`` sum f+ (E,), ``de`` sum (f+ - f-) eps (E, d); and
        ``f_plus`` (n_samples,) the positive sides' returns.
    """
    theta = jnp.asarray(theta)
    d = int(theta.shape[0])
    dtype = theta.dtype
    edges = np.asarray(edges)
    acc = {k: jnp.zeros((d,), jnp.float64 if dtype == jnp.float64 else jnp.float32)
           for k in ("fe", "e", "de")}
    acc["f"] = jnp.zeros((), acc["fe"].dtype)
    out = {k: np.zeros((len(edges),) + tuple(v.shape)) for k, v in acc.items()}
    f_plus = np.zeros(n_samples)
    _chunk_terms = _terms_fn(returns_fn, theta, sigma, chunk)
    if 0 in edges:
        pass  # prefix sums at 0 are zero
    for c, lo in enumerate(range(0, n_samples, chunk)):
        cums, fp = _chunk_terms(jax.random.fold_in(key, c))
        f_plus[lo:lo + chunk] = np.asarray(fp)
        inside = (edges > lo) & (edges <= lo + chunk)
        for j in np.flatnonzero(inside):
            i = int(edges[j] - lo - 1)
            for k in acc:
                out[k][j] = np.asarray(acc[k] + cums[k][i])
        for k in acc:
            acc[k] = acc[k] + cums[k][-1]
    return {**out, "f_plus": f_plus}


def _terms_fn(returns_fn, theta, sigma, chunk):
    d = int(theta.shape[0])

    @jax.jit
    def terms(key):
        eps = jax.random.normal(key, (chunk, d), theta.dtype)
        fp = returns_fn(theta[None, :] + sigma * eps)
        fm = returns_fn(theta[None, :] - sigma * eps)
        acc_t = jnp.float32 if theta.dtype != jnp.float64 else jnp.float64
        fp_, fm_ = fp.astype(acc_t), fm.astype(acc_t)
        e = eps.astype(acc_t)
        return {"fe": jnp.cumsum(fp_[:, None] * e, 0), "e": jnp.cumsum(e, 0),
                "de": jnp.cumsum((fp_ - fm_)[:, None] * e, 0),
                "f": jnp.cumsum(fp_)}, fp
    return terms


def block_estimates(sums: dict, edges, counts, n_samples: int, repeats: int, sigma: float):
    """Estimates per count and block from :func:`stream_sums`.

    Returns ``(reinforce, es)``: dicts ``count -> (k, d)`` arrays of the k block estimates
    with that many rollouts (REINFORCE: n samples; ES: n / 2 pairs, none for n = 1).
    """
    pos = {int(e): j for j, e in enumerate(np.asarray(edges))}

    def block(name, a, b):
        return sums[name][pos[b]] - (sums[name][pos[a]] if a else 0.0)

    rf, es = {}, {}
    for n in (int(x) for x in counts):
        rows = []
        for k in range(min(repeats, n_samples // n)):
            a, b = k * n, (k + 1) * n
            fe, e, f = block("fe", a, b), block("e", a, b), block("f", a, b)
            if n == 1:
                g = fe / sigma
            else:  # leave-one-out baseline: sum (f_i - (S - f_i)/(n-1)) eps_i
                g = (n * fe - f * e) / ((n - 1) * n * sigma)
            rows.append(g)
        if rows:
            rf[n] = np.stack(rows)
        m = n // 2
        rows = []
        if m >= 1:
            for k in range(min(repeats, n_samples // m)):
                a, b = k * m, (k + 1) * m
                rows.append(block("de", a, b) / (2.0 * sigma * m))
        if rows:
            es[n] = np.stack(rows)
    return rf, es


def cosine(est, truth) -> np.ndarray:
    """Cosine of the angle between each row of ``est`` (k, d) and ``truth`` (d,)."""
    est, truth = np.atleast_2d(np.asarray(est, float)), np.asarray(truth, float)
    den = np.linalg.norm(est, axis=1) * np.linalg.norm(truth)
    return np.where(den > 0, est @ truth / np.where(den > 0, den, 1.0), np.nan)


def relative_error(est, truth) -> np.ndarray:
    """``|est_k - truth| / |truth|`` for each row of ``est`` (k, d)."""
    est, truth = np.atleast_2d(np.asarray(est, float)), np.asarray(truth, float)
    return np.linalg.norm(est - truth[None, :], axis=1) / np.linalg.norm(truth)


def first_above(counts, values, threshold: float) -> float:
    """The first count whose value exceeds ``threshold`` and stays above it at every larger
    count of the grid (NaN if none): the rollouts an estimator needs."""
    counts, values = np.asarray(counts, float), np.asarray(values, float)
    ok = np.isfinite(values) & (values > threshold)
    for i in range(len(counts)):
        if ok[i:].all():
            return float(counts[i])
    return float("nan")
