"""Rules on counts of seeds (:mod:`thesis.claims.stats`): "in most runs" and "it happened"
(rule 10), chapter 6's "a configuration works / fails" (:func:`judge_rate`) and "reached
within a budget" (rule 7, :func:`decide_within_budget`).
"""

from __future__ import annotations

import numpy as np

from thesis.claims.intervals import clopper_pearson
from thesis.claims.levels import (
    BUDGET_FACTOR, CONFIDENCE, MIN_SEEDS, ONE_SIDED, SPURIOUS_RATE,
)
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


def exists_needs(n: int, *, replicated: bool, spurious: float = SPURIOUS_RATE) -> int:
    """The fewest seeds of ``n`` that must show an event for "it happened" (rule 10): the
    smallest count k with P(K >= k) <= :data:`ONE_SIDED` when every run passes the success
    criterion by chance at rate ``spurious`` (:data:`SPURIOUS_RATE`), a replicated event
    (the seed's twin run or re-evaluation shows it too, independently) at ``spurious``
    squared; ``n + 1`` when no count of ``n`` seeds can."""
    q = spurious ** 2 if replicated else spurious
    for k in range(1, n + 1):
        if binom_tail(k, n, q, upper=True) <= ONE_SIDED:
            return k
    return n + 1


def decide_exists(flags, *, label: str = "event", replicated=None,
                  spurious: float = SPURIOUS_RATE) -> Verdict:
    """Rule 10, existential: "it happened" (``flags``, one 0/1 per seed; NaN dropped).

    An event counts on a seed only where it repeats: ``replicated`` (one flag per seed,
    the seed's perturbed twin run or the claim's own re-evaluation from fresh starts shows
    it too) must be set there as well. Reproduced when more seeds show a counted event
    than runs passing the criterion by chance would give: at least
    :func:`exists_needs` of them (the exact binomial test against ``spurious`` squared, or
    against ``spurious`` itself when the claim has no replication, at :data:`ONE_SIDED`);
    not_reproduced when none of at least :data:`MIN_SEEDS` seeds shows the event at all;
    inconclusive otherwise (events too few, or not repeated). The rate of the events with
    its Clopper-Pearson interval is reported beside it.
    """
    x = np.asarray(flags, float).ravel()
    ok = np.isfinite(x)
    if replicated is not None:
        r = np.asarray(replicated, float).ravel()
        if r.size != x.size:
            raise ValueError(f"replicated has {r.size} flags for {x.size} seeds")
        ok &= np.isfinite(r)
        counted = (x[ok] > 0.5) & (r[ok] > 0.5)
    else:
        counted = x[ok] > 0.5
    k_raw, n = int((x[ok] > 0.5).sum()), int(ok.sum())
    k = int(counted.sum())
    need = exists_needs(n, replicated=replicated is not None, spurious=spurious)
    lo, hi = clopper_pearson(k_raw, n)
    rep = "replicated by its twin run" if replicated is not None else "unreplicated"
    statistic = (f"existence: number of seeds where {label} ({rep}); exact binomial test "
                 f"against runs passing by chance at {spurious:g} per run"
                 + (" (squared for an event its twin repeats)" if replicated is not None
                    else "") + f" at one-sided {ONE_SIDED:g}; the rate with its "
                 f"Clopper-Pearson {int(CONFIDENCE * 100)} % interval as context")
    measured = {"n_seeds": n, f"n_seeds_{label}": k_raw, "n_seeds_counted": k,
                "n_seeds_needed": need, "replicated": float(replicated is not None), "rate": k_raw / n if n else np.nan,
                "rate_ci_low": lo, "rate_ci_high": hi}
    if n and k >= need:
        return Verdict("reproduced", measured, statistic,
                       f"{label} in {k} of {n} seeds ({rep}; at least {need} needed)")
    if k_raw == 0:
        if n < MIN_SEEDS:
            return Verdict("inconclusive", measured, statistic,
                           f"{label} in none of only {n} seed(s); at least {MIN_SEEDS} are "
                           "needed")
        return Verdict("not_reproduced", measured, statistic, f"{label} in none of {n} seeds")
    seen = (f"{label} in {k_raw} of {n} seeds, {k} of them repeated by their twin run"
            if replicated is not None else f"{label} in {k_raw} of {n} seeds (unreplicated)")
    why = (f"{seen}; existence needs at least {need} such seeds" if need <= n else
           f"{label} in {k_raw} of {n} seeds; {n} seeds cannot tell an event from runs "
           f"passing by chance at {spurious:g}")
    return Verdict("inconclusive", measured, statistic, why)


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
    """Decide "reached within ``budget`` evaluations" from per-seed counts (rule 7): what
    the method does as a rule, so a majority of seeds (rule 10).

    ``reached_at[i]`` is the count at which seed i first met the target (NaN if never);
    ``run_length[i]`` the last count the run reached. A seed *succeeds* when it reached the
    target within ``factor * budget``; it *fails* when it did not although it ran that long;
    otherwise it is *censored* (the run stopped too early to tell). Reproduced when the
    successes show a success rate above 1/2 (exact one-sided binomial test at
    :data:`ONE_SIDED`, censored seeds counted as failures); not_reproduced when the failures
    show it below 1/2 (censored seeds counted as successes); inconclusive otherwise, also
    with fewer than :data:`MIN_SEEDS` seeds. With 5 seeds or fewer even n of n cannot show
    a majority (2^-n > 2.5 %).
    """
    reached_at = np.asarray(reached_at, float).ravel()
    run_length = np.asarray(run_length, float).ravel()
    limit = factor * budget
    success = np.isfinite(reached_at) & (reached_at <= limit)
    fail = ~success & (run_length >= limit)
    n = reached_at.size
    k, f = int(success.sum()), int(fail.sum())
    p_most = binom_tail(k, n, 0.5, upper=True) if n else np.nan
    p_few = binom_tail(f, n, 0.5, upper=True) if n else np.nan
    statistic = (f"per-seed count to reach the target; success within {factor:g} x the "
                 f"thesis's {budget:g} = {limit:g}; exact binomial test of a success rate "
                 f"above 1/2 (one-sided {ONE_SIDED:g}; a censored seed counts against the "
                 "verdict it would support)")
    measured = {"n_seeds": n, "n_success": k, "n_fail": f,
                "n_censored": int(n - k - f), "budget": budget, "limit": limit,
                "p_most": p_most, "p_fewer": p_few,
                f"{label}_median": float(np.nanmedian(reached_at)) if np.isfinite(
                    reached_at).any() else np.nan}
    few = _too_few(n, measured, statistic)
    if few:
        return few
    if p_most <= ONE_SIDED:
        return Verdict("reproduced", measured, statistic,
                       f"{k} of {n} seeds reached the target within {limit:g} "
                       f"(p = {p_most:.3g})")
    if p_few <= ONE_SIDED:
        measured["p_not_reproduced"] = p_few
        return Verdict("not_reproduced", measured, statistic,
                       f"{f} of {n} seeds missed the target within {limit:g} (p = {p_few:.3g})")
    censored = ~success & ~fail
    why = f"{k} of {n} seeds reached the target within {limit:g}, {f} missed it"
    if censored.any():
        why += (f", {int(censored.sum())} stopped at {run_length[censored].max():g} before "
                f"the limit ({factor:g} x the thesis's {budget:g})")
    if binom_tail(n, n, 0.5, upper=True) > ONE_SIDED:
        why += f"; {n} seeds cannot show a majority at {ONE_SIDED:g} (needs at least 6)"
    return Verdict("inconclusive", measured, statistic, why)
