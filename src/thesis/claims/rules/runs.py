"""Rule 9 of :mod:`thesis.claims.stats`: "run A's particles outperform run B's over all
generations" (§4.6) and "A does not harm", over seeds.
"""

from __future__ import annotations

import numpy as np

from thesis.claims.intervals import _failed_flags
from thesis.claims.levels import NOT_WORSE_UNFLAGGED_MIN_SEEDS, RUN_CLAIMS, SMALL_A_EFFECT
from thesis.claims.rules.common import _too_few
from thesis.claims.rules.means import decide_beats, decide_threshold
from thesis.claims.significance import run_statistics
from thesis.claims.types import Verdict


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
    as in :func:`decide_runs_over_generations`.

    Without ``failed`` (runs that carry no failure flag) a "reproduced" needs at least
    :data:`~thesis.claims.levels.NOT_WORSE_UNFLAGGED_MIN_SEEDS` seeds with a finite
    effect: below that, a second mode of seeds nobody flags breaks the t interval's level
    (the calibration's ``bimodal*`` laws), and the verdict is inconclusive, saying how
    many seeds would decide it. "Not reproduced" (the effect's interval below the margin)
    holds its level under those laws and stands at any seed count."""
    e = run_statistics(a, b)["effect"]
    v = decide_threshold(e, bound=-margin, below=False,
                         label=f"A12_{label_a}_vs_{label_b}_minus_half", failed=failed,
                         failure_bounds=failure_bounds)
    statistic = (f"per seed: mean over generations of the Vargha-Delaney A of {label_a} vs "
                 f"{label_b} minus 0.5; " + v.statistic + f" (non-inferiority margin "
                 f"{margin:g}, a small effect)")
    n = int(np.isfinite(e).sum())
    need = NOT_WORSE_UNFLAGGED_MIN_SEEDS
    if v.status == "reproduced" and failed is None and n < need:
        return Verdict("inconclusive", {**v.measured, "n_seeds": n,
                                        "seeds_needed_unflagged": need}, statistic,
                       f"not worse on {n} seeds ({v.detail}), but runs without a failure "
                       f"flag decide \"not worse\" only from {need} seeds on (a second mode "
                       f"of seeds breaks the interval below that: calibration, rule 9)")
    return Verdict(v.status, v.measured, statistic, v.detail)
