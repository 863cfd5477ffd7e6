"""Rules on counts of seeds (:mod:`thesis.claims.stats`): "in most runs" and "it happened"
(rule 10), chapter 6's "a configuration works / fails" (:func:`judge_rate`) and "reached
within a budget" (rule 7, :func:`decide_within_budget`).
"""

from __future__ import annotations

import numpy as np

from thesis.claims.intervals import clopper_pearson
from thesis.claims.levels import BUDGET_FACTOR, CONFIDENCE, MIN_SEEDS, ONE_SIDED
from thesis.claims.rules.common import _too_few
from thesis.claims.significance import binom_tail
from thesis.claims.types import Verdict


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
