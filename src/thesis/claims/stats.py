"""The statistics every claim uses, with one set of rules for the whole pipeline.

Every "reproduced" below promises what the lower tail of a two-sided 95 % interval
promises: under the rule's null it is said at most :data:`ONE_SIDED` (2.5 %) of the time,
at every seed count the profiles run (3, 5, 10; chapter 6's rate rule 6, 10, 20 and 40).
:mod:`thesis.claims.calibration` checks this by simulation per rule, seed count and
per-seed law (normal, exponential, Student t with 2 degrees of freedom; failure mixtures
with 10, 20 and 30 % of runs failed far from the rest; discrete counts), and exactly for
the rate rule; ``tests/claims/test_calibration.py`` asserts it. Which rule reads which
sentence form is listed in :mod:`thesis.claims.forms`.

Rules (applied uniformly by the decision helpers below):

1. **Unit of replication is the seed.** A check first reduces a dataset to one value per
   seed (:func:`per_seed` averages every other dimension it does not compare).
2. **Fewer than** :data:`MIN_SEEDS` **(3) seeds -> inconclusive**, whatever the numbers.
3. **Interval:** mean over seeds with the 95 % **Student t interval**
   (:func:`mean_interval`: mean +- t(0.975, n - 1) s / sqrt(n); zero width when all values
   are equal). *Why this interval:* it was chosen on the calibration simulation alone
   (:func:`thesis.claims.calibration.compare_candidates` and
   :func:`~thesis.claims.calibration.choose_candidate`: the most powerful candidate whose
   false-"reproduced" rate under rule 4's null stays within 3 Monte-Carlo standard errors
   of 2.5 % at 3, 5 and 10 seeds under every law). With 1000 simulated nulls per cell, the
   bootstrap interval used before (BCa) said "A beats B" under no difference in 14 % of
   samples at 3 seeds, 8-10 % at 5 and 4-9 % at 10 (the percentile interval 12 %, 8-9 %,
   5-6 %); an exact sign-flip permutation test and the Wilcoxon signed-rank test hold the
   level but cannot reach it below 6 seeds (the smallest one-sided p is 2^-n); the t
   interval held it everywhere (1.0-2.3 %) with 17 %, 41 % and 83 % power at an advantage
   of 1 sd with 3, 5 and 10 seeds. *Assumptions:* seeds are independent, and the per-seed values
   (rule 4: the paired differences) are distributed symmetrically about their mean or
   close to normally; the paired differences of two methods drawn from one law are
   symmetric whatever that law, which is the null of rules 4, 5 and 9. A per-seed law
   strongly skewed *away* from the claimed side of a bound breaks rule 6 (an exponential
   law: 10-11 % instead of 2.5 % at 3-10 seeds; the sign-flip and Wilcoxon tests 9 % at
   10 seeds); no interval of a mean holds for every law at such n (Bahadur and Savage
   1956), so this is stated, kept visible as a strict expected failure of the calibration
   test, and checks of ratios decide on their logarithm. The same holds for 5 and 10
   seeds of a discrete count skewed away from the claimed side (a count of 4 trials at
   0.8, "above" its mean: about 8 % and 5 %). *Runs that fail* are the extreme of that
   skew: with 80 % of runs near 1.0 and 20 % near 0.2 the t interval said "above the
   mean" in 38 %, 34 % and 12 % of samples at 3, 5 and 10 seeds (3 seeds see no failure
   half the time and the interval trusts them), and "A beats a never-failing B of the
   same mean" in 30 %, 28 % and 10 % (400 draws per cell).
   So the t interval of rules 4-6 and 9 *assumes runs without a failure mode*; a check
   whose runs can fail passes its failure indicator and is decided by rule 3b.
3b. **Runs that fail** (``failed=``: one flag per seed, the chapter's own indicator: fell,
   at chance, diverged; ``failure_bounds=``: the range a failed run's value can take). The
   failure rate and the runs that worked are decided separately
   (:func:`mixture_interval`): the mean over runs is (1 - pi) w + pi phi, with pi in its
   exact Clopper-Pearson interval, w in the t interval of the working runs and phi in the
   declared range (else the t interval of the failed runs), each at a Bonferroni share of
   the level; the interval is the range of the mean over that box. It holds the level under
   every failure mixture of the calibration (0 % false "reproduced" at 3, 5 and 10 seeds,
   rules 4, 5, 6 and 9), and says what it cannot decide: an unseen failure rate at 3 or
   5 seeds is still up to 77 % or 58 %, so no such claim passes there (the power table
   shows from how many seeds one does: with 10 % of runs failing, "mean above 0.6" passes
   in about a third of samples at 10 seeds and nearly always at 40). Without a declared
   range and with fewer than 2 failed runs the failed runs' value is unbounded:
   inconclusive. **Discrete values** (``discrete=True``: counts, capped or rounded values,
   rank statistics): a tie of every seed is what a discrete law gives, not a law without
   spread, so fewer than :data:`TIE_MIN_SEEDS` (6) tied seeds decide nothing (2^-n, the
   sign test's smallest p, reaches 2.5 % from 6 seeds on); the skewed count tied at 3
   seeds in 7 % of samples. Values not declared discrete keep the zero-width interval.
4. **"A beats B"** (:func:`decide_beats`): on paired per-seed differences in the claimed
   direction, *reproduced* when the interval lies above 0, *not_reproduced* when it lies
   below 0, *inconclusive* otherwise.
5. **"A is like B"** (:func:`decide_equivalent`): *reproduced* when the interval of the
   difference lies inside ``(-margin, margin)`` (two one-sided tests at 2.5 % each),
   *not_reproduced* when it lies entirely outside, *inconclusive* otherwise.
6. **"X is below/above a bound"** (:func:`decide_threshold`): the same with one bound.
   **"Some configuration does it"** (:func:`decide_any`): a claim that looks at several
   configurations and holds when one of them does corrects for looking at them all: the
   one-sided t test of rule 6 per configuration, Holm's step-down (:func:`holm`) at
   :data:`ONE_SIDED` over them; *not_reproduced* when every configuration's interval lies
   on the wrong side. A claim that needs *all* of them (:func:`combine`) needs no
   correction for "reproduced" (each part must be), but its "not reproduced" does: any
   of 15 parts at their boundary says "not reproduced" alone in 1 - 0.975^15 = 32 % of
   samples. So a part contradicts the whole only at the family level: Holm over the
   parts' one-sided p of their "not reproduced" (its first step: the smallest p times the
   number of parts at most :data:`ONE_SIDED`); for 15 parts at 3, 5 and 10 seeds the
   calibration measures 2.9 %, 3.0 % and 2.8 % at 3000 draws (Bonferroni's bound 2.47 %,
   Monte-Carlo standard error 0.3 %). A part whose verdict carries
   no p (a check's own logic) contradicts the whole uncorrected.
7. **Comparisons with a published number** allow a relative tolerance of
   :data:`PUBLISHED_TOLERANCE` (25 %); **counts of evaluations or updates** allow a
   factor :data:`BUDGET_FACTOR` (2) over the thesis's count (:func:`decide_within_budget`).
8. **Timings** are measurements, not seeded outcomes: :func:`decide_measurement` compares
   the median over repeats with the bound, without an interval; "roughly a factor F"
   (:func:`decide_roughly`) is a band from F / :data:`ROUGHLY` to F x :data:`ROUGHLY`.
9. **"Run A's particles outperform run B's over all generations"** (§4.6,
   :func:`decide_runs_over_generations`). The thesis ran one optimisation per arm and
   compared them with a Wilcoxon rank-sum test per generation, the p-values combined
   with Fisher's method. With several seeds, each seed s gives that statistic, ``p_s``
   (one-sided "A greater", or two-sided), and an effect ``e_s``: the mean over
   generations of the Vargha-Delaney A (the probability that a particle of A outscores
   one of B, ties half) minus 0.5. Rule 4 on the ``e_s`` (against 0) is the method-level
   evidence E; ``k`` counts the seeds with ``p_s`` below the thesis's bound.

   - *"A significantly better (p < bound)"*: reproduced when E is reproduced and
     k > n/2; not_reproduced when E says B is better, or when k = 0 (no run reaches the
     thesis's significance); inconclusive otherwise.
   - *"A not significantly better (p > bound)"*: reproduced when n - k > n/2 and either E
     is not reproduced or the interval of the effect stays below a small effect
     (:data:`SMALL_A_EFFECT`: pooling seeds may detect an advantage too small to matter,
     which no single run would call significant); not_reproduced when E is reproduced and
     k > n/2; inconclusive otherwise.
   - *"no significant difference"* (two-sided p): reproduced when n - k > n/2 and either E
     is inconclusive or the interval of the effect lies within +-:data:`SMALL_A_EFFECT`;
     not_reproduced when E is decisive (either way) and k > n/2; inconclusive otherwise.
   - *"A does not harm"* (:func:`decide_not_worse`): rule 6 on the ``e_s`` with the bound
     -:data:`SMALL_A_EFFECT` (non-inferiority by less than a small effect).
10. **"It happens in most runs"** (:func:`decide_majority`): the exact one-sided binomial
    test of "the event's rate is at most 1/2" (equivalently the Clopper-Pearson 95 %
    interval of the rate above 1/2): reproduced when p <= :data:`ONE_SIDED`,
    not_reproduced when the mirror test says the rate is below 1/2, inconclusive
    otherwise. With 5 seeds or fewer even n of n cannot reach the level (2^-n > 2.5 %):
    inconclusive, and the reason says so. **"It happened"** (an existential sentence,
    :func:`decide_exists`): reproduced when at least one seed shows the event (a found
    object is found whatever the rate), not_reproduced when none of at least
    :data:`MIN_SEEDS` does; the count k of n is in the detail. **"A configuration works /
    fails"** (:func:`judge_rate`, chapter 6): "works" needs the exact binomial test of its
    success rate against the rate of a configuration that fails at :data:`ONE_SIDED` and
    no such test against the rate of one that works; "fails" the mirror. From 26 seeds on
    both tests can reject (at 40 seeds 14-17 successes: a rate shown above a failing one
    and below a working one): such a count is *unclear*, a band between "fails" (0-13 of
    40) and "works" (18-40 of 40); at a true rate of 0.34 the rule said "works" in 51 % and
    "fails" in 49 % of samples without the band. Its power at 6, 10, 20 and 40 seeds is in
    the calibration module's power table.
11. **A profile that cannot test the sentence as stated** (a budget, network, batch or
    duration smaller than the thesis's; a quantity not measured) gives *inconclusive*
    with the gap in the detail (:func:`untestable`), never *reproduced*; a run that
    contradicts the claim even at the smaller scale may still be *not_reproduced* where
    the smaller scale can only make the claim easier, as each check says.
"""

from __future__ import annotations

import contextlib
import contextvars
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy import stats as sps

from thesis.claims.types import Verdict

MIN_SEEDS = 3
CONFIDENCE = 0.95
#: One-sided level of every "reproduced": the lower tail of the two-sided 95 % interval.
ONE_SIDED = round((1.0 - CONFIDENCE) / 2.0, 12)
#: The interval of rules 3-6 (chosen by :mod:`thesis.claims.calibration`).
INTERVAL_METHOD = "Student t"
#: Bootstrap resamples of :func:`bootstrap_mean` (the interval the rules used before; kept
#: as a candidate of the calibration comparison, no rule uses it).
N_RESAMPLES = 9999
BOOTSTRAP_SEED = 20180101
ALPHA = 0.05
PUBLISHED_TOLERANCE = 0.25
BUDGET_FACTOR = 2.0
#: A - 0.5 of a small effect in Vargha and Delaney's A (2000: A = 0.56 small, 0.64
#: medium, 0.71 large): rule 9's non-inferiority margin.
SMALL_A_EFFECT = 0.06
#: The claims rule 9 decides.
RUN_CLAIMS = ("better", "not_better", "no_difference")
#: "roughly a factor F": within a factor 2 either side of F (log-symmetric). The thesis calls
#: its own Tab. 7.1 ratios of 5.5 to 7.7 "roughly a factor 10", which this band contains.
ROUGHLY = 2.0

#: Discrete per-seed values (``discrete=True``: counts, capped or rounded values, rank
#: statistics) that are all equal over fewer seeds than this decide nothing (rule 3b): a
#: tie of every seed is what a discrete law gives, not a law without spread, and the sign
#: test's smallest one-sided p, 2^-n, reaches :data:`ONE_SIDED` only from 6 seeds on.
TIE_MIN_SEEDS = int(np.ceil(np.log2(1.0 / ONE_SIDED)))

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


def per_seed(da: xr.DataArray, keep: Sequence[str] = ()) -> xr.DataArray:
    """Average every dimension except ``seed`` and ``keep`` (NaN skipped).

    A dataset without a ``seed`` dimension gives one pseudo-seed, so it counts as n = 1.
    Returns a DataArray with dims ``("seed", *keep)``.
    """
    if "seed" not in da.dims:
        da = da.expand_dims(seed=[0])
    other = [d for d in da.dims if d not in ("seed", *keep)]
    if other:
        da = da.mean(other, skipna=True)
    return da.transpose("seed", *keep)


def _too_few(n: int, measured: dict, statistic: str) -> Verdict | None:
    if n < MIN_SEEDS:
        return Verdict("inconclusive", measured, statistic,
                       f"only {n} seed(s) with values; at least {MIN_SEEDS} are needed")
    return None


def _interval_words(ci: Interval) -> str:
    if ci.method in ("t", "degenerate"):
        return (f"mean with {int(CONFIDENCE * 100)} % {INTERVAL_METHOD} interval "
                f"({ci.method}; assumes runs without a failure mode, rule 3)")
    if ci.method == "mixture":
        return (f"mean with its {int(CONFIDENCE * 100)} % interval over runs that fail "
                "(failure rate by Clopper-Pearson, working runs by Student t, failed runs "
                "by their declared range; rule 3b)")
    return f"mean with {int(CONFIDENCE * 100)} % {INTERVAL_METHOD} interval ({ci.method})"


def _interval(x: np.ndarray, failed, failure_bounds, confidence: float = CONFIDENCE, *,
              discrete: bool = False) -> Interval:
    """Rule 3's t interval of ``x``, or rule 3b's :func:`mixture_interval` when per-seed
    ``failed`` flags are given."""
    if failed is None:
        if failure_bounds is not None:
            raise ValueError("failure_bounds needs failed flags")
        return mean_interval(x, confidence=confidence)
    return mixture_interval(x, failed, failure_bounds=failure_bounds, confidence=confidence,
                            discrete=discrete)


def _tied(ci: Interval, measured: dict, statistic: str, discrete: bool) -> Verdict | None:
    """Inconclusive when the values are ``discrete`` and every one of fewer than
    :data:`TIE_MIN_SEEDS` seeds has the same value (rule 3b): a zero-width interval is a
    tie, not certainty."""
    if discrete and ci.method == "degenerate" and ci.n < TIE_MIN_SEEDS:
        return Verdict("inconclusive", measured, statistic,
                       f"all {ci.n} seeds have the same value ({ci.mean:.4g}): a tie of fewer "
                       f"than {TIE_MIN_SEEDS} seeds does not show a law without spread "
                       f"(sign test: 2^-{ci.n} > {ONE_SIDED:g})")
    return None


def _p_wrong_side(x: np.ndarray, failed, failure_bounds, wrong, t_p) -> float:
    """One-sided p of the verdict "not_reproduced" (the interval on the wrong side):
    ``t_p()`` for the t interval, else the level at which the mixture interval gets
    there (:func:`_interval_p`); used by :func:`combine`'s correction."""
    if failed is None:
        return float(t_p())
    return _interval_p(lambda c: _interval(x, failed, failure_bounds, c), wrong)


def decide_beats(a, b, *, higher_is_better: bool, label_a: str = "a",
                 label_b: str = "b", failed=None,
                 failure_bounds: tuple[float, float] | None = None,
                 discrete: bool = False) -> Verdict:
    """Decide "A beats B" from paired per-seed values ``a`` and ``b`` (rule 4).

    ``a[i]`` and ``b[i]`` belong to the same seed; pairs with a NaN are dropped. The
    interval is that of the per-seed advantage of A (rule 3). With ``failed`` (one flag
    per seed: A's or B's run failed there) the interval is rule 3b's
    (:func:`mixture_interval`), ``failure_bounds`` the range of the advantage on a seed
    whose run failed. ``discrete``: the values are counts or otherwise discrete, so a tie
    of every seed decides nothing below :data:`TIE_MIN_SEEDS` seeds (rule 3b).
    """
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    ok = np.isfinite(a) & np.isfinite(b)
    f = None if failed is None else _failed_flags(failed, a.size)[ok]
    a, b = a[ok], b[ok]
    sign = 1.0 if higher_is_better else -1.0
    adv = sign * (a - b)  # > 0 where A is better
    ci = _interval(adv, f, failure_bounds, discrete=discrete)
    better = "higher" if higher_is_better else "lower"
    statistic = (f"paired per-seed advantage of {label_a} over {label_b} ({better} is better): "
                 + _interval_words(ci))
    measured = {f"mean_{label_a}": float(a.mean()) if a.size else np.nan,
                f"mean_{label_b}": float(b.mean()) if b.size else np.nan,
                "advantage_mean": ci.mean, "advantage_ci_low": ci.low,
                "advantage_ci_high": ci.high, "n_seeds": ci.n,
                "p_one_sided": t_pvalue(adv, greater=True) if f is None else np.nan}
    if f is not None:
        measured["n_seeds_failed"] = int(f.sum())
    few = _too_few(ci.n, measured, statistic) or _tied(ci, measured, statistic, discrete)
    if few:
        return few
    if ci.low > 0:
        return Verdict("reproduced", measured, statistic,
                       f"{label_a} is better than {label_b}: interval of the advantage above 0")
    if ci.high < 0:
        measured["p_not_reproduced"] = _p_wrong_side(
            adv, f, failure_bounds, lambda c: c.high < 0,
            lambda: t_pvalue(adv, greater=False))
        return Verdict("not_reproduced", measured, statistic,
                       f"{label_b} is better than {label_a}: interval of the advantage below 0")
    return Verdict("inconclusive", measured, statistic,
                   "the interval of the advantage includes 0")


def decide_fewer_censored(a, a_done, b, b_done, *, label_a: str = "a",
                          label_b: str = "b") -> Verdict:
    """Decide "A needs less than B" (rule 4) from per-seed costs until success, some censored.

    ``a[i]`` is what method A spent on seed i (iterations, evaluations or seconds): its
    cost until success where ``a_done[i]``, else what it spent without succeeding, a lower
    bound of its unknown cost (right-censored); likewise ``b``. A seed is *kept* when both
    succeeded, or when one failed after spending at least what the other needed to succeed
    (it lost that seed whatever its true cost). Seeds where both failed, or where the failed
    side stopped before the other succeeded, tell nothing and are dropped. Rule 4
    (:func:`decide_beats`, lower is better) on the kept seeds, with a failed side's spent
    cost in place of its unknown one: that understates the failed side's cost, so a verdict
    against a side with failures stands, while one in its favour is reported inconclusive.
    """
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    ad, bd = np.asarray(a_done, bool).ravel(), np.asarray(b_done, bool).ravel()
    ok = np.isfinite(a) & np.isfinite(b)
    keep = ok & ((ad & bd) | (~ad & bd & (a >= b)) | (ad & ~bd & (b >= a)))
    v = decide_beats(a[keep], b[keep], higher_is_better=False, label_a=label_a,
                     label_b=label_b)
    measured = {**v.measured, "n_seeds_run": int(a.size), "n_seeds_dropped": int((~keep).sum()),
                f"{label_a}_failed_kept": int((keep & ~ad).sum()),
                f"{label_b}_failed_kept": int((keep & ~bd).sum()),
                f"{label_a}_succeeded": int(ad.sum()), f"{label_b}_succeeded": int(bd.sum())}
    statistic = (v.statistic + "; a run that never succeeded counts with what it spent (a lower "
                 "bound) on seeds where that is at least the other method's cost to success, "
                 "seeds where both failed or the failed run stopped first are dropped")
    favoured_failed = ((v.status == "reproduced" and (keep & ~ad).any())
                       or (v.status == "not_reproduced" and (keep & ~bd).any()))
    if favoured_failed:
        return Verdict("inconclusive", measured, statistic,
                       "the favoured method has failed runs, whose true cost is unknown")
    return Verdict(v.status, measured, statistic, v.detail)


def decide_equivalent(diff, *, margin: float, label: str = "difference", failed=None,
                      failure_bounds: tuple[float, float] | None = None,
                      discrete: bool = False) -> Verdict:
    """Decide "equivalent within ``margin``" from per-seed differences ``diff`` (rule 5);
    with ``failed`` flags (and the range of a failed seed's difference,
    ``failure_bounds``) on rule 3b's interval; ``discrete`` as in :func:`decide_beats`."""
    d = np.asarray(diff, float).ravel()
    ci = _interval(d, failed, failure_bounds, discrete=discrete)
    statistic = (f"per-seed {label}: {_interval_words(ci)} against the equivalence margin "
                 f"+-{margin:g}")
    measured = {f"{label}_mean": ci.mean, f"{label}_ci_low": ci.low,
                f"{label}_ci_high": ci.high, "margin": margin, "n_seeds": ci.n}
    few = _too_few(ci.n, measured, statistic) or _tied(ci, measured, statistic, discrete)
    if few:
        return few
    if -margin < ci.low and ci.high < margin:
        return Verdict("reproduced", measured, statistic, "interval inside the margin")
    if ci.low >= margin or ci.high <= -margin:
        measured["p_not_reproduced"] = _p_wrong_side(
            d, failed, failure_bounds, lambda c: c.low >= margin or c.high <= -margin,
            lambda: min(t_pvalue(d, null=margin, greater=True),
                        t_pvalue(d, null=-margin, greater=False)))
        return Verdict("not_reproduced", measured, statistic, "interval outside the margin")
    return Verdict("inconclusive", measured, statistic, "interval straddles the margin")


def decide_threshold(values, *, bound: float, below: bool, label: str = "value",
                     failed=None, failure_bounds: tuple[float, float] | None = None,
                     discrete: bool = False) -> Verdict:
    """Decide "the mean of ``values`` is below (``below=True``) or above ``bound``" (rule 6);
    with per-seed ``failed`` flags (and a failed run's value range ``failure_bounds``) on
    rule 3b's interval (:func:`mixture_interval`); ``discrete`` as in
    :func:`decide_beats`."""
    x = np.asarray(values, float).ravel()
    ci = _interval(x, failed, failure_bounds, discrete=discrete)
    side = "below" if below else "above"
    statistic = f"per-seed {label}: {_interval_words(ci)} {side} {bound:g}"
    measured = {f"{label}_mean": ci.mean, f"{label}_ci_low": ci.low,
                f"{label}_ci_high": ci.high, "bound": bound, "n_seeds": ci.n}
    if failed is not None:
        measured["n_seeds_failed"] = int(_failed_flags(failed, x.size)[np.isfinite(x)].sum())
    few = _too_few(ci.n, measured, statistic) or _tied(ci, measured, statistic, discrete)
    if few:
        return few
    good, bad = (ci.high < bound, ci.low > bound) if below else (ci.low > bound, ci.high < bound)
    if good:
        return Verdict("reproduced", measured, statistic, f"interval {side} {bound:g}")
    if bad:
        measured["p_not_reproduced"] = _p_wrong_side(
            x, failed, failure_bounds,
            (lambda c: c.low > bound) if below else (lambda c: c.high < bound),
            lambda: t_pvalue(x, null=bound, greater=below))
        return Verdict("not_reproduced", measured, statistic,
                       f"interval on the wrong side of {bound:g}")
    return Verdict("inconclusive", measured, statistic, f"interval contains {bound:g}")


def decide_any(groups: dict[str, np.ndarray], *, bound: float, below: bool,
               label: str = "value", discrete: bool = False) -> Verdict:
    """Decide "for some configuration the mean is below (above) ``bound``" (rule 6, Holm).

    ``groups`` maps a configuration's name to its per-seed values. Each configuration
    gets the one-sided t test of rule 6 (:func:`t_pvalue`); Holm's step-down over all of
    them at :data:`ONE_SIDED` decides which hold. Reproduced when at least one holds;
    not_reproduced when every configuration's own 95 % interval lies on the wrong side of
    ``bound`` (none can hold); inconclusive otherwise (also with fewer than
    :data:`MIN_SEEDS` seeds in every configuration). ``discrete`` as in
    :func:`decide_beats`: a configuration whose discrete values tie is no evidence.
    """
    names = list(groups)
    side = "below" if below else "above"
    cis = {g: mean_interval(groups[g]) for g in names}
    p = np.array([t_pvalue(groups[g], null=bound, greater=not below)
                  if cis[g].n >= MIN_SEEDS and not (discrete and cis[g].method == "degenerate"
                                                    and cis[g].n < TIE_MIN_SEEDS)
                  else np.nan for g in names])
    held = holm(p)
    statistic = (f"per configuration, per-seed {label}: one-sided t test of the mean {side} "
                 f"{bound:g}, Holm's correction over the {len(names)} configurations at "
                 f"{ONE_SIDED:g}; {int(CONFIDENCE * 100)} % {INTERVAL_METHOD} intervals")
    measured: dict = {"bound": bound, "n_configurations": len(names),
                      "n_configurations_holding": int(held.sum())}
    for g, pg in zip(names, p):
        measured.update({f"{g}.{label}_mean": cis[g].mean, f"{g}.{label}_ci_low": cis[g].low,
                         f"{g}.{label}_ci_high": cis[g].high, f"{g}.p_one_sided": pg,
                         f"{g}.n_seeds": cis[g].n})
    if held.any():
        which = ", ".join(g for g, h in zip(names, held) if h)
        return Verdict("reproduced", measured, statistic,
                       f"{label} {side} {bound:g} for {which} (Holm over {len(names)} "
                       "configurations)")
    wrong = [(c.n >= MIN_SEEDS)
             and not (discrete and c.method == "degenerate" and c.n < TIE_MIN_SEEDS)
             and ((c.low > bound) if below else (c.high < bound)) for c in cis.values()]
    if names and all(wrong):
        # every configuration on the wrong side: the largest of their p (intersection-union)
        measured["p_not_reproduced"] = max(
            t_pvalue(groups[g], null=bound, greater=below) for g in names)
        return Verdict("not_reproduced", measured, statistic,
                       f"every configuration's interval lies on the wrong side of {bound:g}")
    if all(c.n < MIN_SEEDS for c in cis.values()):
        return Verdict("inconclusive", measured, statistic,
                       f"fewer than {MIN_SEEDS} seeds in every configuration")
    return Verdict("inconclusive", measured, statistic,
                   f"no configuration holds after Holm's correction over {len(names)}; "
                   "not every one is on the wrong side")


def decide_measurement(value: float, *, bound: float, below: bool, label: str) -> Verdict:
    """Decide a timing-like measurement (median over repeats) against ``bound`` (rule 8)."""
    side = "below" if below else "above"
    statistic = f"{label} (median over repeats, a measurement without interval) {side} {bound:g}"
    measured = {label: value, "bound": bound}
    if not np.isfinite(value):
        return Verdict("inconclusive", measured, statistic, f"{label} is not finite")
    ok = value < bound if below else value > bound
    return Verdict("reproduced" if ok else "not_reproduced", measured, statistic,
                   f"{label} = {value:.3g} is {'' if ok else 'not '}{side} {bound:g}")


def decide_roughly(values, *, factor: float, label: str) -> Verdict:
    """Decide "roughly a factor ``factor``" from measured ratios ``values`` (rule 8).

    Reproduced when every finite ratio lies in ``[factor / ROUGHLY, factor * ROUGHLY]``;
    not_reproduced when their geometric mean lies outside it; inconclusive when the mean is
    inside but some ratios are not.
    """
    x = np.asarray(values, float).ravel()
    x = x[np.isfinite(x) & (x > 0)]
    lo, hi = factor / ROUGHLY, factor * ROUGHLY
    gmean = float(np.exp(np.log(x).mean())) if x.size else float("nan")
    statistic = (f"{label}: every measured ratio (no interval) within roughly a factor "
                 f"{factor:g}, i.e. [{lo:g}, {hi:g}]")
    measured = {f"{label}_gmean": gmean, f"{label}_min": float(x.min()) if x.size else np.nan,
                f"{label}_max": float(x.max()) if x.size else np.nan, "band_low": lo,
                "band_high": hi, "n_configurations": float(x.size)}
    if not x.size:
        return Verdict("inconclusive", measured, statistic, f"no finite {label}")
    inside = (x >= lo) & (x <= hi)
    if inside.all():
        return Verdict("reproduced", measured, statistic,
                       f"every {label} ({x.min():.3g} to {x.max():.3g}) is in [{lo:g}, {hi:g}]")
    if not lo <= gmean <= hi:
        return Verdict("not_reproduced", measured, statistic,
                       f"geometric mean {gmean:.3g} is outside [{lo:g}, {hi:g}]")
    return Verdict("inconclusive", measured, statistic,
                   f"geometric mean {gmean:.3g} is in the band but {int((~inside).sum())} of "
                   f"{x.size} ratios are not")


def untestable(gaps: list[str], measured: dict | None = None, statistic: str = "") -> Verdict:
    """*Inconclusive* because the profile cannot test the sentence as stated (rule 11)."""
    return Verdict("inconclusive", dict(measured or {}), statistic,
                   "not testable as stated at this profile: " + "; ".join(gaps))


def first_reaching(curve: xr.DataArray, dim: str, threshold: float) -> np.ndarray:
    """Per seed, the first coordinate of ``dim`` where ``curve < threshold`` (NaN if never).

    ``curve`` has dims ``("seed", dim)``; coordinates of ``dim`` count evaluations/updates.
    """
    steps = np.asarray(curve[dim].values, dtype=float)
    below = np.asarray(curve.values < threshold)
    out = np.full(below.shape[0], np.nan)
    for i, row in enumerate(below):
        hit = np.flatnonzero(row)
        if hit.size:
            out[i] = steps[hit[0]]
    return out


def decide_within_budget(reached_at, run_length, *, budget: float, label: str,
                         factor: float = BUDGET_FACTOR) -> Verdict:
    """Decide "reached within ``budget`` evaluations" from per-seed counts (rule 7).

    ``reached_at[i]`` is the count at which seed i first met the target (NaN if never);
    ``run_length[i]`` the last count the run reached. A seed *succeeds* when it reached the
    target within ``factor * budget``; it *fails* when it did not although it ran that long;
    otherwise it is *censored* (the run stopped too early to tell). With fewer than
    :data:`MIN_SEEDS` seeds inconclusive; else reproduced when all succeed, not_reproduced
    when more than half fail, inconclusive otherwise.
    """
    reached_at = np.asarray(reached_at, float).ravel()
    run_length = np.asarray(run_length, float).ravel()
    limit = factor * budget
    success = np.isfinite(reached_at) & (reached_at <= limit)
    fail = ~success & (run_length >= limit)
    n = reached_at.size
    statistic = (f"per-seed count to reach the target; success within {factor:g} x the "
                 f"thesis's {budget:g} = {limit:g}")
    measured = {"n_seeds": n, "n_success": int(success.sum()), "n_fail": int(fail.sum()),
                "n_censored": int(n - success.sum() - fail.sum()), "budget": budget,
                "limit": limit,
                f"{label}_median": float(np.nanmedian(reached_at)) if np.isfinite(
                    reached_at).any() else np.nan}
    few = _too_few(n, measured, statistic)
    if few:
        return few
    if fail.sum() * 2 > n:
        return Verdict("not_reproduced", measured, statistic,
                       f"{int(fail.sum())} of {n} seeds missed the target within {limit:g}")
    if success.all():
        return Verdict("reproduced", measured, statistic,
                       f"all {n} seeds reached the target within {limit:g}")
    censored = ~success & ~fail
    if censored.any():
        return Verdict("inconclusive", measured, statistic,
                       f"{int(censored.sum())} of {n} seeds stopped at {run_length[censored].max():g} "
                       f"before the limit {limit:g} ({factor:g} x the thesis's {budget:g}) "
                       "without reaching the target; "
                       f"{int(success.sum())} reached it, {int(fail.sum())} missed it")
    return Verdict("inconclusive", measured, statistic,
                   f"{int(fail.sum())} of {n} seeds missed the target within {limit:g}")


def combine(parts: dict[str, Verdict], *, statistic: str = "") -> Verdict:
    """All parts must hold (rule 6's multi-part claim): reproduced if all are (an
    intersection of tests needs no correction); not_reproduced when a part contradicts
    the claim at the family level: Holm over the parts' one-sided p of their
    "not_reproduced" (``measured["p_not_reproduced"]``), whose first step is Bonferroni,
    so the smallest such p times the number of parts at most :data:`ONE_SIDED`; a
    not_reproduced part that carries no p (a count, a check's own logic) contradicts the
    whole uncorrected, as it says. Else inconclusive.

    ``not_run`` parts make the whole ``not_run``; measured numbers are prefixed by part
    name, and the whole's ``p_not_reproduced`` is the Bonferroni-adjusted smallest p.
    """
    statuses = [v.status for v in parts.values()]
    m = len(parts)
    against = {name: v.measured.get("p_not_reproduced", np.nan)
               for name, v in parts.items() if v.status == "not_reproduced"}
    ps = [float(p) for p in against.values() if isinstance(p, float) and np.isfinite(p)]
    bare = [name for name, p in against.items()
            if not (isinstance(p, float) and np.isfinite(p))]
    p_family = min(1.0, m * min(ps)) if ps else np.nan
    note = ""
    if "not_run" in statuses:
        status = "not_run"
    elif bare or (ps and p_family <= ONE_SIDED):
        status = "not_reproduced"
    elif all(s == "reproduced" for s in statuses):
        status = "reproduced"
    else:
        status = "inconclusive"
        if against:
            note = (f"{', '.join(against)} not reproduced alone, not at the family level "
                    f"(Holm over {m} parts: {m} x p = {p_family:.3g} > {ONE_SIDED:g}); ")
    measured = {f"{name}.{k}": v for name, verdict in parts.items()
                for k, v in verdict.measured.items()}
    if status == "not_reproduced" and not bare:
        measured["p_not_reproduced"] = p_family
    detail = note + "; ".join(f"{name}: {v.status} ({v.detail})" for name, v in parts.items())
    stat = statistic or "all of: " + "; ".join(
        f"{name}: {v.statistic}" for name, v in parts.items())
    if m > 1:
        stat += f" (a part contradicts the whole after Holm's correction over the {m} parts)"
    return Verdict(status, measured, stat, detail)


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


def decide_runs_over_generations(a, b, *, bound: float, claim: str, label_a: str = "a",
                                 label_b: str = "b", failed=None,
                                 failure_bounds: tuple[float, float] | None = None
                                 ) -> Verdict:
    """Decide rule 9 for runs ``a`` and ``b`` ((S, G, N) scores, see :func:`run_statistics`).

    ``claim`` is ``"better"`` (A significantly better, p < ``bound``), ``"not_better"``
    (A not significantly better, p > ``bound``) or ``"no_difference"`` (two-sided p >
    ``bound``). The measured numbers list every seed's p and effect. ``failed`` (one flag
    per seed: a run of that seed failed) and ``failure_bounds`` (the effect's range on
    such a seed) put the effect's interval on rule 3b.
    """
    if claim not in RUN_CLAIMS:
        raise ValueError(f"claim must be one of {RUN_CLAIMS}, got {claim!r}")
    st = run_statistics(a, b)
    p = st["p_two_sided"] if claim == "no_difference" else st["p_greater"]
    ok = np.isfinite(p) & np.isfinite(st["effect"])
    f = None if failed is None else _failed_flags(failed, ok.size)[ok]
    p, e = p[ok], st["effect"][ok]
    n = int(p.size)
    k = int((p < bound).sum())
    eff = decide_beats(e, np.zeros_like(e), higher_is_better=True,
                       label_a=f"A12_{label_a}_vs_{label_b}", label_b="chance", failed=f,
                       failure_bounds=failure_bounds)
    sided = "two-sided" if claim == "no_difference" else f"one-sided ({label_a} greater)"
    statistic = (f"per seed: Fisher-combined per-generation Wilcoxon rank-sum p ({sided}) "
                 f"and the mean over generations of the Vargha-Delaney A of {label_a} vs "
                 f"{label_b} minus 0.5; rule 4 on that effect over seeds, and the number of "
                 f"seeds with p < {bound:g}")
    measured = {"n_seeds": n, "n_seeds_p_below_bound": k, "bound": bound,
                "median_p": float(np.median(p)) if n else np.nan,
                "effect_mean": eff.measured.get("advantage_mean", np.nan),
                "effect_ci_low": eff.measured.get("advantage_ci_low", np.nan),
                "effect_ci_high": eff.measured.get("advantage_ci_high", np.nan),
                **{f"p_seed{i}": float(v) for i, v in enumerate(p)},
                **{f"effect_seed{i}": float(v) for i, v in enumerate(e)}}
    few = _too_few(n, measured, statistic)
    if few:
        return few
    majority_sig, majority_not = 2 * k > n, 2 * (n - k) > n
    where = f"{k} of {n} seeds have p < {bound:g}"
    E = eff.status
    lo, hi = measured["effect_ci_low"], measured["effect_ci_high"]
    below_small = bool(np.isfinite(hi) and hi < SMALL_A_EFFECT)
    within_small = below_small and bool(np.isfinite(lo) and lo > -SMALL_A_EFFECT)
    if claim == "better":
        if E == "not_reproduced":
            # the effect's own p, so that combine can correct this part over a claim's parts
            measured["p_not_reproduced"] = eff.measured["p_not_reproduced"]
            return Verdict("not_reproduced", measured, statistic,
                           f"{label_b} outperforms {label_a} over seeds ({eff.detail}); {where}")
        if k == 0:
            return Verdict("not_reproduced", measured, statistic,
                           f"no seed reaches the thesis's p < {bound:g} (effect: {E})")
        if E == "reproduced" and majority_sig:
            return Verdict("reproduced", measured, statistic,
                           f"{label_a} outperforms {label_b} over seeds; {where}")
        return Verdict("inconclusive", measured, statistic, f"effect: {E}; {where}")
    if claim == "not_better":
        if majority_not and (E != "reproduced" or below_small):
            why = (f"no consistent advantage of {label_a} (effect: {E})" if E != "reproduced"
                   else f"{label_a}'s advantage over seeds is below a small effect "
                        f"(A - 0.5 < {SMALL_A_EFFECT:g})")
            return Verdict("reproduced", measured, statistic, f"{why}; {where}")
        if E == "reproduced" and majority_sig:
            return Verdict("not_reproduced", measured, statistic,
                           f"{label_a} significantly outperforms {label_b}; {where}")
        return Verdict("inconclusive", measured, statistic, f"effect: {E}; {where}")
    if majority_not and (E == "inconclusive" or within_small):
        why = ("no consistent difference (effect interval includes 0)" if E == "inconclusive"
               else f"any difference is below a small effect (|A - 0.5| < {SMALL_A_EFFECT:g})")
        return Verdict("reproduced", measured, statistic, f"{why}; {where}")
    if E != "inconclusive" and majority_sig:
        return Verdict("not_reproduced", measured, statistic,
                       f"the runs differ consistently ({eff.detail}); {where}")
    return Verdict("inconclusive", measured, statistic, f"effect: {E}; {where}")


def decide_not_worse(a, b, *, margin: float = SMALL_A_EFFECT, label_a: str = "a",
                     label_b: str = "b", failed=None,
                     failure_bounds: tuple[float, float] | None = None) -> Verdict:
    """Rule 9, "A does not harm": rule 6 on the per-seed effect (mean A12 - 0.5 of runs
    ``a`` vs ``b``, (S, G, N) scores) above ``-margin``; ``failed`` / ``failure_bounds``
    as in :func:`decide_runs_over_generations`."""
    e = run_statistics(a, b)["effect"]
    v = decide_threshold(e, bound=-margin, below=False,
                         label=f"A12_{label_a}_vs_{label_b}_minus_half", failed=failed,
                         failure_bounds=failure_bounds)
    statistic = (f"per seed: mean over generations of the Vargha-Delaney A of {label_a} vs "
                 f"{label_b} minus 0.5; " + v.statistic + f" (non-inferiority margin "
                 f"{margin:g}, a small effect)")
    return Verdict(v.status, v.measured, statistic, v.detail)


def _count(flags) -> tuple[int, int]:
    """(events, seeds) of per-seed 0/1 ``flags`` (NaN dropped)."""
    x = np.asarray(flags, float).ravel()
    x = x[np.isfinite(x)]
    return int((x > 0.5).sum()), int(x.size)


def decide_majority(flags, *, label: str = "event") -> Verdict:
    """Rule 10: does the event (``flags``, one 0/1 per seed; NaN dropped) occur in most
    runs? Exact one-sided binomial tests of the rate against 1/2 at :data:`ONE_SIDED`."""
    k, n = _count(flags)
    lo, hi = clopper_pearson(k, n)
    p_most = binom_tail(k, n, 0.5, upper=True) if n else np.nan
    p_few = binom_tail(k, n, 0.5, upper=False) if n else np.nan
    statistic = (f"number of seeds where {label}: exact binomial test of a rate above 1/2 "
                 f"(one-sided {ONE_SIDED:g}; Clopper-Pearson {int(CONFIDENCE * 100)} % "
                 "interval)")
    measured = {"n_seeds": n, f"n_seeds_{label}": k, "rate_ci_low": lo, "rate_ci_high": hi,
                "p_most": p_most, "p_fewer": p_few}
    few = _too_few(n, measured, statistic)
    if few:
        return few
    if p_most <= ONE_SIDED:
        return Verdict("reproduced", measured, statistic,
                       f"{label} in {k} of {n} seeds (p = {p_most:.3g})")
    if p_few <= ONE_SIDED:
        measured["p_not_reproduced"] = p_few
        return Verdict("not_reproduced", measured, statistic,
                       f"{label} in only {k} of {n} seeds (p = {p_few:.3g})")
    if binom_tail(n, n, 0.5, upper=True) > ONE_SIDED:
        return Verdict("inconclusive", measured, statistic,
                       f"{label} in {k} of {n} seeds; with {n} seeds even {n} of {n} cannot "
                       f"show a majority at the one-sided {ONE_SIDED:g} level (needs at "
                       "least 6 seeds)")
    return Verdict("inconclusive", measured, statistic,
                   f"{label} in {k} of {n} seeds: neither most nor few at {ONE_SIDED:g}")


def decide_exists(flags, *, label: str = "event") -> Verdict:
    """Rule 10, existential: "it happened" (``flags``, one 0/1 per seed; NaN dropped).

    Reproduced when at least one seed shows the event (the rate is reported, not
    decided); not_reproduced when none of at least :data:`MIN_SEEDS` seeds does;
    inconclusive when none of fewer seeds does.
    """
    k, n = _count(flags)
    lo, hi = clopper_pearson(k, n)
    statistic = (f"existence: number of seeds where {label} (at least one needed; rate with "
                 f"its Clopper-Pearson {int(CONFIDENCE * 100)} % interval as context)")
    measured = {"n_seeds": n, f"n_seeds_{label}": k, "rate": k / n if n else np.nan,
                "rate_ci_low": lo, "rate_ci_high": hi}
    if k:
        return Verdict("reproduced", measured, statistic, f"{label} in {k} of {n} seeds")
    if n < MIN_SEEDS:
        return Verdict("inconclusive", measured, statistic,
                       f"{label} in none of only {n} seed(s); at least {MIN_SEEDS} are needed")
    return Verdict("not_reproduced", measured, statistic, f"{label} in none of {n} seeds")


def rate_pvalues(k: int, n: int, *, works_rate: float, fails_rate: float) -> tuple[float, float]:
    """(p that the success rate exceeds ``fails_rate``, p that it is below ``works_rate``):
    exact binomial tails of ``k`` successes in ``n`` seeds (:func:`judge_rate`)."""
    if n == 0:
        return float("nan"), float("nan")
    return (binom_tail(k, n, fails_rate, upper=True), binom_tail(k, n, works_rate, upper=False))


def judge_rate(k: int, n: int, *, works_rate: float, fails_rate: float) -> str:
    """``"works"``, ``"fails"`` or ``"unclear"`` for ``k`` successes in ``n`` seeds.

    Each verdict needs its own one-sided exact binomial test at :data:`ONE_SIDED` and the
    other's silence: works when the test rejects "the rate is at most ``fails_rate``" (a
    configuration that fails) and the rate is not shown below ``works_rate``; fails when
    the test rejects "the rate is at least ``works_rate``" and the rate is not shown above
    ``fails_rate``; unclear otherwise (neither test rejects, or both do: a rate shown to lie
    between the two, as 14-17 of 40), and below :data:`MIN_SEEDS` seeds (rule 10).
    """
    if n < MIN_SEEDS:
        return "unclear"
    p_works, p_fails = rate_pvalues(k, n, works_rate=works_rate, fails_rate=fails_rate)
    above, below = p_works <= ONE_SIDED, p_fails <= ONE_SIDED
    if above and not below:
        return "works"
    if below and not above:
        return "fails"
    return "unclear"


def reachable(n: int, *, works_rate: float, fails_rate: float) -> tuple[bool, bool]:
    """Whether ``n`` seeds can show "works" (all succeed) and "fails" (none succeeds) at
    :data:`ONE_SIDED` at all (:func:`judge_rate`)."""
    p_works, _ = rate_pvalues(n, n, works_rate=works_rate, fails_rate=fails_rate)
    _, p_fails = rate_pvalues(0, n, works_rate=works_rate, fails_rate=fails_rate)
    return bool(p_works <= ONE_SIDED), bool(p_fails <= ONE_SIDED)
