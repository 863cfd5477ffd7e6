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
   whose runs can fail passes its failure indicator and is decided by rule 3b. The
   calibration keeps this visible: with 10-30 % of seeds at an unflagged second mode,
   rule 4 said "reproduced" in 5-33 %, rule 6 "above" in 4-46 % and rule 9 "not worse"
   in 4-12 % of samples at 3-10 seeds (rules 5, 6 "below" and 9 "better" held); rule 9's
   "not worse" held from 40 seeds, so without a failure flag it decides "reproduced"
   only from there (:data:`~thesis.claims.levels.NOT_WORSE_UNFLAGGED_MIN_SEEDS`). The
   chapters' indicators: chapter 2 a network at chance, chapter 3 a robot that fell,
   chapter 5 a classifier whose train accuracy does not beat the train set's majority
   share, chapter 7's gait and §8.2's arms a run that diverged or never improved on
   its recorded curve; each declares the range a failed run's value can take.
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
   "Reached within the budget" is what the method does as a rule, so its seeds are read
   as rule 10's majority: reproduced when the successes show a rate above 1/2 (a
   censored seed counts as a failure there, as a success in the mirror test). Reading
   "every seed succeeded" instead said "reproduced" at a true rate of 1/2 in 12.5 % of
   3-seed samples (calibration: 12-13 %; now 0 % at 3 and 5 seeds, which cannot show a
   majority, about 1 % at 10).
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
    :func:`decide_exists`): an event counts on a seed only when it repeats, in the seed's
    perturbed twin run or the claim's own re-evaluation (``replicated=``); reproduced when
    more seeds show a counted event than runs that pass the success criterion by chance
    at :data:`SPURIOUS_RATE` (5 %) would give (exact binomial test at :data:`ONE_SIDED`
    against 5 % squared for repeated events, against 5 % for a claim without a
    replication: :func:`exists_needs`, e.g. 1 of 5 and 2 of 40 repeated seeds, 2 of 3 and
    6 of 40 unrepeated ones); not_reproduced when none of at least :data:`MIN_SEEDS` seeds
    shows it; the count k of n is in the detail. One seed sufficing said "it happened"
    with no event in 34-87 % of 40-seed samples at a spurious rate of 1-5 % (now at most
    2.5 %, the calibration's false-existence rows). **"A configuration works /
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

# The rules' one name space: every chapter reads them as ``stats.<name>``.
from thesis.claims.intervals import (  # noqa: F401
    Interval, bootstrap_mean, clopper_pearson, mean_interval, mixture_interval, resamples,
)
from thesis.claims.levels import (  # noqa: F401
    ALPHA, BOOTSTRAP_SEED, BUDGET_FACTOR, CONFIDENCE, INTERVAL_METHOD, MIN_SEEDS, N_RESAMPLES,
    ONE_SIDED, PUBLISHED_TOLERANCE, ROUGHLY, RUN_CLAIMS, SMALL_A_EFFECT, SPURIOUS_RATE,
    TIE_MIN_SEEDS,
)
from thesis.claims.rules.common import (  # noqa: F401
    _too_few, combine, first_reaching, per_seed, untestable,
)
from thesis.claims.rules.counts import (  # noqa: F401
    decide_exists, decide_majority, decide_within_budget, exists_needs, judge_rate, rate_pvalues,
    reachable,
)
from thesis.claims.rules.means import (  # noqa: F401
    decide_any, decide_beats, decide_equivalent, decide_fewer_censored, decide_threshold,
)
from thesis.claims.rules.measurements import decide_measurement, decide_roughly  # noqa: F401
from thesis.claims.rules.runs import decide_not_worse, decide_runs_over_generations  # noqa: F401
from thesis.claims.significance import (  # noqa: F401
    binom_tail, fisher_combine, holm, mann_whitney, run_statistics, t_pvalue, vargha_delaney,
    wilcoxon_paired,
)
