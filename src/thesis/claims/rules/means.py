"""Rules 4-6 of :mod:`thesis.claims.stats` on a mean over seeds: "A beats B" (:func:`decide_beats`,
also with censored costs), "A is like B" (:func:`decide_equivalent`), "X is below/above a
bound" (:func:`decide_threshold`) and "some configuration does it" (:func:`decide_any`).
"""

from __future__ import annotations

import numpy as np

from thesis.claims.intervals import (
    _failed_flags, _interval_p, Interval, mean_interval, mixture_interval,
)
from thesis.claims.levels import CONFIDENCE, INTERVAL_METHOD, MIN_SEEDS, ONE_SIDED, TIE_MIN_SEEDS
from thesis.claims.rules.common import _too_few
from thesis.claims.significance import holm, t_pvalue
from thesis.claims.types import Verdict


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
