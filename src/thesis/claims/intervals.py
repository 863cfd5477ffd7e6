"""Intervals of a mean over seeds (rules 3 and 3b of :mod:`thesis.claims.stats`): the Student t
interval, the interval over runs that fail (:func:`mixture_interval`), the exact interval of a
rate (:func:`clopper_pearson`) and the bootstrap interval the rules used before.
"""

from __future__ import annotations

import contextlib
import contextvars
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats as sps

from thesis.claims.levels import BOOTSTRAP_SEED, CONFIDENCE, MIN_SEEDS, N_RESAMPLES, TIE_MIN_SEEDS


_RESAMPLES: contextvars.ContextVar[int] = contextvars.ContextVar("n_resamples",
                                                                default=N_RESAMPLES)


@contextlib.contextmanager
def resamples(n: int) -> Iterator[None]:
    """Use ``n`` resamples in :func:`bootstrap_mean` inside the block (config
    ``report.bootstrap_resamples``; the decision rules do not resample)."""
    if n < 100:
        raise ValueError(f"at least 100 bootstrap resamples, got {n}")
    token = _RESAMPLES.set(int(n))
    try:
        yield
    finally:
        _RESAMPLES.reset(token)


@dataclass(frozen=True)
class Interval:
    """Mean over seeds with an interval.

    Attributes:
        mean: sample mean of the finite values.
        low, high: interval bounds (NaN when n < 2).
        n: number of finite values.
        method: ``"t"`` (:func:`mean_interval`), ``"BCa"`` or ``"percentile"``
            (:func:`bootstrap_mean`), ``"degenerate"`` (all equal), ``"single"`` or
            ``"none"`` (no values).
    """

    mean: float
    low: float
    high: float
    n: int
    method: str


def _finite(values: Sequence[float] | np.ndarray) -> np.ndarray:
    x = np.asarray(values, dtype=float).ravel()
    return x[np.isfinite(x)]


def _trivial_interval(x: np.ndarray) -> Interval | None:
    """The interval of finite values ``x`` where no method is needed: none (no values),
    a single value, or a zero-width one (all equal); None otherwise."""
    if x.size == 0:
        return Interval(np.nan, np.nan, np.nan, 0, "none")
    mean = float(x.mean())
    if x.size == 1:
        return Interval(mean, np.nan, np.nan, 1, "single")
    if np.ptp(x) == 0:
        return Interval(mean, mean, mean, x.size, "degenerate")
    return None


def mean_interval(values, *, confidence: float = CONFIDENCE) -> Interval:
    """Mean of ``values`` (1-D, one per seed; NaN dropped) and its Student t interval
    (rule 3): mean +- t((1 + confidence) / 2, n - 1) s / sqrt(n), zero width when every
    value is equal."""
    x = _finite(values)
    trivial = _trivial_interval(x)
    if trivial is not None:
        return trivial
    n, mean = x.size, float(x.mean())
    half = float(sps.t.ppf((1.0 + confidence) / 2.0, n - 1) * x.std(ddof=1) / np.sqrt(n))
    return Interval(mean, mean - half, mean + half, n, "t")


def _failed_flags(failed, size: int) -> np.ndarray:
    """``failed`` (one truthy flag per seed) as a bool array of ``size``; ValueError on a
    length mismatch."""
    f = np.asarray(failed).ravel()
    if f.size != size:
        raise ValueError(f"failed has {f.size} flags for {size} seeds")
    return f.astype(bool)


def _mix(rate: float, work: float, fail: float) -> float:
    """(1 - rate) work + rate fail, with a zero weight cancelling an infinite value."""
    return (0.0 if rate >= 1.0 else (1.0 - rate) * work) + (0.0 if rate <= 0.0 else rate * fail)


def mixture_interval(values, failed, *, failure_bounds: tuple[float, float] | None = None,
                     confidence: float = CONFIDENCE, discrete: bool = False) -> Interval:
    """Interval of the mean of per-seed ``values`` whose runs sometimes fail (rule 3b).

    The mean over runs is (1 - pi) w + pi phi: pi the failure rate, w the mean of a run
    that works, phi that of a failed run. Each is bounded separately: pi by its exact
    Clopper-Pearson interval from the count of ``failed`` seeds, w by the Student t
    interval of the seeds that worked, phi by ``failure_bounds`` (the range a failed run's
    value can take, declared by the chapter: at chance, fallen, diverged) or else by the
    t interval of the failed seeds (unbounded with fewer than 2). The interval is the range
    of the mean over that box; each of its 2 or 3 parts is taken at confidence
    1 - (1 - ``confidence``) / parts, so each end of the interval errs at most
    (1 - ``confidence``) / 2 (Bonferroni). Unseen failures are what this guards against:
    with no failure among n seeds pi may still be up to 1 - (alpha/parts)^(1/n), so a
    failure range far from the working runs keeps the interval wide.

    Args:
        values: (n,) per-seed values (NaN dropped with their flags).
        failed: (n,) per-seed flags, truthy where that seed's run failed.
        failure_bounds: (low, high) of a failed run's value, in the values' units.
        discrete: the values are discrete: a part whose values all tie over fewer than
            :data:`TIE_MIN_SEEDS` seeds is unbounded.

    Returns:
        :class:`Interval` with method ``"mixture"`` (``"none"`` without values).
    """
    x = np.asarray(values, float).ravel()
    f = _failed_flags(failed, x.size)
    keep = np.isfinite(x)
    x, f = x[keep], f[keep]
    n = x.size
    if n == 0:
        return Interval(np.nan, np.nan, np.nan, 0, "none")
    if failure_bounds is not None:
        lo_f, hi_f = (float(v) for v in failure_bounds)
        if not lo_f <= hi_f:
            raise ValueError(f"failure_bounds must be (low, high), got {failure_bounds}")
    parts = 2 if failure_bounds is not None else 3
    level = 1.0 - (1.0 - confidence) / parts
    k = int(f.sum())
    p_lo, p_hi = clopper_pearson(k, n, confidence=level)

    def bounds(v: np.ndarray) -> tuple[float, float]:
        ci = mean_interval(v, confidence=level)
        if ci.n < 2 or (discrete and ci.method == "degenerate" and ci.n < TIE_MIN_SEEDS):
            return -np.inf, np.inf
        return ci.low, ci.high

    w_lo, w_hi = bounds(x[~f]) if k < n else (-np.inf, np.inf)
    if failure_bounds is None:
        lo_f, hi_f = bounds(x[f])
    low = min(_mix(p, w_lo, lo_f) for p in (p_lo, p_hi))
    high = max(_mix(p, w_hi, hi_f) for p in (p_lo, p_hi))
    return Interval(float(x.mean()), float(low), float(high), n, "mixture")


def _interval_p(make, wrong) -> float:
    """The smallest one-sided level a at which the interval ``make(1 - 2 a)`` satisfies
    ``wrong`` (its p-value; 1 when not even at a = 0.5): bisection on a log scale."""
    lo, hi = 1e-12, 0.5
    if not wrong(make(1.0 - 2.0 * hi)):
        return 1.0
    if wrong(make(1.0 - 2.0 * lo)):
        return lo
    for _ in range(40):
        mid = float(np.sqrt(lo * hi))
        if wrong(make(1.0 - 2.0 * mid)):
            hi = mid
        else:
            lo = mid
    return hi


def clopper_pearson(k: int, n: int, *, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The exact (Clopper-Pearson) interval of a rate from ``k`` events in ``n`` trials."""
    if n == 0:
        return float("nan"), float("nan")
    tail = (1.0 - confidence) / 2.0  # the beta-quantile form of the exact interval
    low = float(sps.beta.ppf(tail, k, n - k + 1)) if k > 0 else 0.0
    high = float(sps.beta.ppf(1.0 - tail, k + 1, n - k)) if k < n else 1.0
    return low, high


def bootstrap_mean(values, *, confidence: float = CONFIDENCE, n_resamples: int | None = None,
                   seed: int = BOOTSTRAP_SEED) -> Interval:
    """Mean of ``values`` (1-D, one per seed; NaN dropped) and its bootstrap interval.

    The interval the rules used before the calibration (BCa, percentile when BCa fails or
    n < 3); kept as a candidate of :func:`thesis.claims.calibration.compare_candidates`.
    ``n_resamples`` defaults to :data:`N_RESAMPLES` or the value set by :func:`resamples`.
    """
    n_resamples = _RESAMPLES.get() if n_resamples is None else n_resamples
    x = _finite(values)
    trivial = _trivial_interval(x)
    if trivial is not None:
        return trivial
    n, mean = x.size, float(x.mean())
    methods = ("BCa", "percentile") if n >= MIN_SEEDS else ("percentile",)
    for method in methods:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                res = sps.bootstrap((x,), np.mean, confidence_level=confidence,
                                    n_resamples=n_resamples, method=method,
                                    rng=np.random.default_rng(seed))
            except (ValueError, FloatingPointError):
                continue
        lo, hi = float(res.confidence_interval.low), float(res.confidence_interval.high)
        if np.isfinite(lo) and np.isfinite(hi):
            return Interval(mean, lo, hi, n, method)
    return Interval(mean, np.nan, np.nan, n, "none")
