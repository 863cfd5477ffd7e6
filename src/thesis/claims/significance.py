"""Significance tests the rules use (:mod:`thesis.claims.stats`): the one-sided t test dual to
the t interval, Holm's step-down, exact binomial tails, rank tests, Fisher's combination and
the per-seed statistics of two optimisation runs (rule 9).
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy import stats as sps

from thesis.claims.intervals import _finite
from thesis.claims.levels import ONE_SIDED


def t_pvalue(values, *, null: float = 0.0, greater: bool = True) -> float:
    """One-sided p of the t test that the mean of ``values`` (NaN dropped) is above
    (``greater``) or below ``null``; the test dual to :func:`mean_interval`.

    All values equal: 0 when they lie on the claimed side of ``null``, else 1. NaN with
    fewer than 2 values.
    """
    x = _finite(values) - null
    if x.size < 2:
        return float("nan")
    sign = 1.0 if greater else -1.0
    if np.ptp(x) == 0:
        return 0.0 if sign * x[0] > 0 else 1.0
    t = sign * x.mean() / (x.std(ddof=1) / np.sqrt(x.size))
    return float(sps.t.sf(t, x.size - 1))


def holm(pvalues, *, alpha: float = ONE_SIDED) -> np.ndarray:
    """Holm's step-down rejections (bool per p-value, NaN never rejected) at family-wise
    level ``alpha``: sort the m p-values, reject the i-th smallest (i = 0, 1, ...) while
    p <= alpha / (m - i)."""
    p = np.asarray(pvalues, float).ravel()
    p = np.where(np.isfinite(p), p, np.inf)
    out = np.zeros(p.size, bool)
    for i, j in enumerate(np.argsort(p, kind="stable")):
        if p[j] > alpha / (p.size - i):
            break
        out[j] = True
    return out


def binom_tail(k: int, n: int, p: float, *, upper: bool) -> float:
    """P(K >= k) (``upper``) or P(K <= k) for K ~ Binomial(n, p): the exact one-sided p of
    a count ``k`` of ``n`` against the rate ``p``."""
    return float(sps.binom.sf(k - 1, n, p) if upper else sps.binom.cdf(k, n, p))


def wilcoxon_paired(a, b, alternative: str = "two-sided") -> float:
    """p-value of the Wilcoxon signed-rank test on paired ``a - b`` (NaN pairs dropped).

    Returns 1.0 when every difference is zero and NaN with no pairs.
    """
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    ok = np.isfinite(a) & np.isfinite(b)
    d = a[ok] - b[ok]
    if d.size == 0:
        return float("nan")
    if np.all(d == 0):
        return 1.0
    return float(sps.wilcoxon(d, alternative=alternative).pvalue)


def mann_whitney(a, b, alternative: str = "two-sided") -> float:
    """p-value of the Mann-Whitney U (Wilcoxon rank-sum) test of independent ``a``, ``b``."""
    a, b = _finite(a), _finite(b)
    if a.size == 0 or b.size == 0:
        return float("nan")
    return float(sps.mannwhitneyu(a, b, alternative=alternative).pvalue)


def fisher_combine(pvalues) -> float:
    """Fisher's method: one p-value from independent p-values (as §4.6 combines generations)."""
    p = _finite(pvalues)
    if p.size == 0:
        return float("nan")
    return float(sps.combine_pvalues(p, method="fisher").pvalue)


def vargha_delaney(a, b) -> float:
    """Vargha-Delaney A of independent samples ``a``, ``b``: P(a > b) + P(a = b)/2, the
    Mann-Whitney U of ``a`` over n_a n_b (NaN dropped; NaN if a sample is empty)."""
    a, b = _finite(a), _finite(b)
    if a.size == 0 or b.size == 0:
        return float("nan")
    return float(sps.mannwhitneyu(a, b).statistic / (a.size * b.size))


def _run_statistics_batched(a, b) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(S, G) A12 and (S,) Fisher-combined one- and two-sided p of finite (S, G, N) runs,
    with scipy's tests vectorised over seeds and generations (the same tests as
    :func:`mann_whitney` and :func:`fisher_combine` one generation at a time)."""
    greater = sps.mannwhitneyu(a, b, alternative="greater", axis=-1)
    two = sps.mannwhitneyu(a, b, alternative="two-sided", axis=-1)
    a12 = np.asarray(greater.statistic, float) / (a.shape[-1] * b.shape[-1])
    p1 = np.asarray(sps.combine_pvalues(greater.pvalue, method="fisher", axis=-1).pvalue)
    p2 = np.asarray(sps.combine_pvalues(two.pvalue, method="fisher", axis=-1).pvalue)
    return a12, p1, p2


def run_statistics(a, b) -> dict[str, np.ndarray]:
    """Per-seed statistics of rule 9 for runs ``a`` and ``b``.

    Args:
        a, b: (S, G, N) scores of every particle of run A and run B, per seed (paired by
            seed) and generation.

    Returns:
        dict of (S,) arrays: ``p_greater`` (Fisher-combined per-generation one-sided
        rank-sum p, A greater), ``p_two_sided`` (the same, two-sided), ``effect`` (mean
        over generations of A12 - 0.5) and (S, G) ``a12`` (Vargha-Delaney A per
        generation).
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.ndim != 3 or b.ndim != 3 or a.shape[:2] != b.shape[:2]:
        raise ValueError(f"runs must be (seed, generation, particle) with equal seeds and "
                         f"generations, got {a.shape} and {b.shape}")
    if np.isfinite(a).all() and np.isfinite(b).all() and a.shape[0] and a.shape[1]:
        a12, p1, p2 = _run_statistics_batched(a, b)
    else:  # NaN particles are dropped per generation: one generation at a time
        a12 = np.array([[vargha_delaney(x, y) for x, y in zip(ra, rb)]
                        for ra, rb in zip(a, b)])
        p1 = np.array([fisher_combine([mann_whitney(x, y, "greater") for x, y in zip(ra, rb)])
                       for ra, rb in zip(a, b)])
        p2 = np.array([fisher_combine([mann_whitney(x, y, "two-sided")
                                       for x, y in zip(ra, rb)]) for ra, rb in zip(a, b)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        effect = np.nanmean(a12, axis=1) - 0.5
    return dict(p_greater=p1, p_two_sided=p2, effect=effect, a12=a12)
