"""Decision helpers for sentence forms the rules of :mod:`thesis.claims.stats` leave open.

They compose the rules of :mod:`thesis.claims.stats` (nothing here changes a rule's level):

- :func:`decide_ratio_like`: "A is like B" / "about F times" for a *ratio*, decided on its
  logarithm as rule 3 says ratios must be (a ratio's spread is multiplicative; the raw
  ratio is skewed and breaks rule 3's symmetry assumption). The published relative
  tolerance ``t`` (rule 7) becomes the log margin ``log(1 + t)``, the smaller of the two
  sides ``log(1 + t)`` and ``-log(1 - t)``, so the log band never admits a ratio the
  linear band would refuse.
- :func:`better_than_chance`: per cell, the exact one-sided binomial test of an error rate
  against the error of a classifier that learned nothing (a similarity between networks
  at chance says nothing about the transforms they use).
- :func:`decide_majority_or_untestable`: rule 10's "in most runs", made *untestable* with
  the seed count it needs when no count of the run's seeds could decide it.
- :func:`min_seeds_for_majority`: that seed count.

Sentence forms (one logic per form). Existential sentences ("was found",
"can", "is possible", "we were able to") are decided as existence (rule 10's
:func:`~thesis.claims.stats.decide_exists`: some seed shows it, the rate beside it);
sentences about what usually happens as means or rates over seeds; a stated size as an
equivalence on the size; a causal sentence needs an intervention. The claims of
chapters 2-5, 7 and §8 that a form decides, and the form each is read as; the claims whose runs can
fail also name the chapter's failure indicator they pass to rule 3b
(:func:`~thesis.claims.stats.mixture_interval`):

======================================================  ====================================
claim                                                   form read
======================================================  ====================================
ch2.chirpz_similar_to_bilinear, ..._no_skew             likeness of two error rates: rule 5
                                                        on the log ratio, gated on every
                                                        compared cell beating chance
ch2.spatial_transformers_beat_plain,                    runs that fail (rule 3b): rule 4 with
ch2.recurrent_beats_feedforward, §8.1's                 a seed failed where a compared
ch8.ch2_prior_in_architecture_beats_cnn                 network is flagged ``failed`` or not
                                                        better than chance; a failed seed's
                                                        difference anywhere in +-100 points
ch2.chirpz_reaches_1_8_percent ("able to achieve")      existence over configurations: some
                                                        configuration's mean below the bound
                                                        (rule 6, Holm over configurations)
ch3.scapulae_larger_turning_radius ("36 % higher")      a size: rule 5 on the log ratio
                                                        about log 1.36
ch3.half_ellipse_beats_sine_at_high_speed,              runs that fail (rule 3b): a seed
ch3.half_ellipse_fastest, ch3.spline_fastest,           failed where the robot fell
ch3.sine_speed_flattens_above_1hz, §8.1's               (``fallen``) in a compared cell
ch8.ch3_biological_trajectory_beats_sine (fig3_4);      (gait and frequency, or turning
ch3.scapulae_needed_for_fast_turning,                   strategy); no declared range for a
ch3.scapulae_larger_turning_radius, the rule-4 and      fallen robot's speed, angular speed
rule-6 parts of ch8.ch3_scapulae_help_maintain_speed    or radius
(table3_2)
ch3.scapulae_maintain_speed ("it is possible")          existence: a seed whose turning
                                                        speed keeps the straight-line speed
ch8.ch3_scapulae_help_maintain_speed ("helps")          usual behaviour (rule 4, rule 6 on
                                                        the log ratio to straight-line
                                                        speed) and existence of a turn
                                                        without scapulae
ch3.turning_without_scapulae_possible                   existence of a stable step-size
                                                        turn; "more slowly" by rule 4
ch3.sine_speed_flattens_above_1hz                       a shape at a place: rule 6 on the
                                                        slope up to 1 Hz and on the slope
                                                        above 1 Hz against half of it
ch3.three_turning_strategies_fail                       each of three: rule 4 per strategy,
                                                        Holm over the three
ch3.sine_gaits_fragile ("not robust")                   absolute: rule 6, fraction walking
                                                        below 1/2
ch4.speedup_from_reduced_search_space, §8.1's           causal: untestable (rule 11) without
ch8.ch4_reduced_exploration                             an intervention; both correlations
                                                        decided and shown
ch4.pebbles_head_start_lost ("all outperform")          every particle: rule 6 on the worst
                                                        original particle's A - 0.5
ch4.pebbles_best_is_transferred                         usual behaviour (rule 10), untestable
                                                        below the 6 seeds it needs
ch4.best_speed_gains, search_space_1_7_times_smaller,   a published ratio: rule 5 on the log
transfer_starts_with_final_search_space                 ratio
ch5.reservoir_better_with_few_sensors ("drastic"),      a size: rule 6 on the difference
ch8.ch5_memory_important ("important")                  above a margin fixed from the
                                                        thesis's own numbers
ch5.generalises_to_frequencies_not_gaits                "not very effective": rule 6, gait
                                                        recall below half-way from chance;
                                                        and rule 4 frequencies over gaits
ch5 comparisons (every gated claim)                     a comparison where no compared
                                                        method classifies: inconclusive
ch5.train_test_gap                                      a gap: rule 4, train over test,
                                                        gated on train beating its majority
ch7.vision_control_learned_through_camera ("can")       existence (as §8.1's pendulum claim)
ch8.coopt_joint_optimisation_possible ("can")           feasibility: existence
ch8.coopt_gradient_needs_fewer_rollouts_*               a count: rule 6 on log10, only where
                                                        a positive control holds
ch8.coopt_analytic_gradient_spread                      runs that fail (rule 3b): a probe
(``_explodes_with_horizon``)                            point whose gradients were not
                                                        finite (``start_nonfinite``) is
                                                        failed, its value the score
                                                        ``EXPLODED`` (10 decades)
======================================================  ====================================

Not yet read with a failure indicator: chapter 4's best-particle comparisons (a fall is
recorded only in the score, below -1, and no range of a failed seed's difference is
declared, so rule 3b would leave them undecided whenever no seed fell); chapter 5 and
chapter 7 record no per-seed failure flag for the claims that read per-seed values
(chapter 7's censored counts carry their own ``converged`` flags, read by
:func:`~thesis.claims.stats.decide_fewer_censored`).
"""

from __future__ import annotations

import numpy as np
from scipy import stats as sps

from thesis.claims import stats
from thesis.claims.types import Verdict

#: Per-digit error of a classifier that learned nothing among 10 digit classes.
CHANCE_ERROR = 0.9


def log_margin(tolerance: float) -> float:
    """The log margin of a relative tolerance ``t``: ``min(log(1 + t), -log(1 - t))``."""
    if not 0 < tolerance < 1:
        raise ValueError(f"a relative tolerance must lie in (0, 1), got {tolerance}")
    return float(min(np.log1p(tolerance), -np.log1p(-tolerance)))


def gain_log_margin(gain: float, tolerance: float = stats.PUBLISHED_TOLERANCE) -> float:
    """The log margin about ``log(1 + gain)`` of a published relative gain (0.09 for "9 %
    faster") whose *gain* is allowed the relative ``tolerance``: the band
    ``[(1 - t) gain, (1 + t) gain]`` on the ratio ``1 + gain``, its smaller log side."""
    if not gain > 0:
        raise ValueError(f"a published gain must be positive, got {gain}")
    return float(min(np.log1p((1 + tolerance) * gain) - np.log1p(gain),
                     np.log1p(gain) - np.log1p((1 - tolerance) * gain)))


def decide_ratio_like(num, den, *, target: float = 1.0,
                      tolerance: float = stats.PUBLISHED_TOLERANCE, label: str = "ratio",
                      margin: float | None = None, failed=None) -> Verdict:
    """Decide "``num / den`` is ``target`` within a relative ``tolerance``" on the log ratio.

    Args:
        num, den: per-seed positive values (1-D, paired by seed); a pair with a value that is
            not finite or not positive has no ratio and is dropped (counted in
            ``n_seeds_without_ratio``).
        target: the ratio the sentence states (1 for "like", 1.36 for "36 % higher").
        tolerance: relative tolerance, turned into the log margin :func:`log_margin`.
        margin: an explicit log margin instead (for a tolerance stated on another scale).
        label: name of the ratio in the measured numbers.
        failed: (n,) per-seed failure flags (the chapter's indicator), for rule 3b's
            interval (:func:`thesis.claims.stats.mixture_interval`, no declared range of a
            failed seed's log ratio); a pair without a ratio is dropped with its flag.

    Returns:
        Rule 5 (:func:`thesis.claims.stats.decide_equivalent`) on ``log(num/den) -
        log(target)``; the measured numbers add the ratio's geometric mean and its interval
        (the log interval exponentiated) and the target.
    """
    if not target > 0:
        raise ValueError(f"the target ratio must be positive, got {target}")
    num, den = np.asarray(num, float).ravel(), np.asarray(den, float).ravel()
    if num.shape != den.shape:
        raise ValueError(f"num and den must pair by seed, got {num.shape} and {den.shape}")
    ok = np.isfinite(num) & np.isfinite(den) & (num > 0) & (den > 0)
    logr = np.where(ok, np.log(np.where(ok, num, 1.0) / np.where(ok, den, 1.0)), np.nan)
    m = log_margin(tolerance) if margin is None else float(margin)
    f = None if failed is None else np.asarray(failed, bool).ravel()
    if f is not None and f.shape != num.shape:
        raise ValueError(f"failed has {f.size} flags for {num.size} seeds")
    v = stats.decide_equivalent(logr[ok] - np.log(target), margin=m,
                                label=f"log_{label}_minus_log_target",
                                failed=None if f is None else f[ok])
    key = f"log_{label}_minus_log_target"
    gm = {f"{label}_geometric_mean": float(np.exp(np.mean(logr[ok]))) if ok.any() else np.nan,
          f"{label}_ci_low": float(target * np.exp(v.measured.get(f"{key}_ci_low", np.nan))),
          f"{label}_ci_high": float(target * np.exp(v.measured.get(f"{key}_ci_high", np.nan))),
          f"{label}_target": float(target), "log_margin": m,
          "n_seeds_without_ratio": int((~ok).sum())}
    statistic = (f"per-seed log of the {label} minus log {target:g}: " + v.statistic
                 + f" (a relative tolerance on the log scale: the ratio within a factor "
                 f"{np.exp(m):.4g} of {target:g})")
    return Verdict(v.status, {**v.measured, **gm}, statistic, v.detail)


def better_than_chance(errors, n_test: int, *, chance: float = CHANCE_ERROR,
                       alpha: float = stats.ONE_SIDED) -> np.ndarray:
    """Per cell, whether an error rate is significantly below ``chance``.

    Args:
        errors: error rates (fractions, any shape; NaN is never better than chance).
        n_test: test items the rates were counted on. Counted conservatively over what is
            independent (chapter 2: the test sequences, whose digits share a canvas and a
            model state), the count is ``round(error * n_test)``.
        chance: the error of a classifier that learned nothing.
        alpha: one-sided level of the exact binomial test P(X <= k | n_test, chance).

    Returns:
        bool array shaped like ``errors``. "Every compared cell beats chance" is an
        intersection of these tests, which needs no multiplicity correction.
    """
    if int(n_test) < 1:
        raise ValueError(f"n_test must be a positive count, got {n_test}")
    err = np.asarray(errors, float)
    out = np.zeros(err.shape, bool)
    fin = np.isfinite(err)
    k = np.round(np.clip(np.where(fin, err, 1.0), 0.0, 1.0) * int(n_test))
    p = sps.binom.cdf(k, int(n_test), chance)
    out[fin] = p[fin] < alpha
    return out


def min_seeds_for_majority(alpha: float = stats.ONE_SIDED) -> int:
    """The fewest seeds at which n of n can show "most runs" (rule 10): 2^-n <= ``alpha``."""
    return int(np.ceil(-np.log2(alpha)))


def decide_majority_or_untestable(flags, *, label: str = "event") -> Verdict:
    """Rule 10's "in most runs" (:func:`thesis.claims.stats.decide_majority`), *untestable*
    (rule 11) when the run's seed count cannot decide it whatever the count: then the
    reason names the seeds it needs (:func:`min_seeds_for_majority`)."""
    v = stats.decide_majority(flags, label=label)
    n = int(v.measured.get("n_seeds", 0))
    need = min_seeds_for_majority()
    if v.status == "inconclusive" and n < need:
        return stats.untestable(
            [f"{n} seeds; no count of {n} can show '{label}' in most runs or in few at the "
             f"one-sided {stats.ONE_SIDED:g} level: at least {need} seeds are needed"],
            {**v.measured, "seeds_needed": need}, v.statistic)
    return v
