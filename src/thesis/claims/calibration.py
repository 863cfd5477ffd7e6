"""Calibration and power of the decision rules of :mod:`thesis.claims.stats`, by simulation.

A rule is *calibrated* when, under its null (no true difference; a mean exactly at the
bound or the margin; an event that occurs in exactly half the runs; a configuration that
fails), it says "reproduced" at most as often as its nominal one-sided level,
:data:`thesis.claims.stats.ONE_SIDED` (2.5 %, the lower tail of a two-sided 95 % interval).
:func:`false_reproduced` simulates each rule's null with per-seed values drawn from one of
:data:`LAWS` and counts how often the rule calls it reproduced; :func:`calibration_table`
does so per rule, seed count and law. The interval of rules 3-6 was chosen on this table
alone (see the module text of :mod:`thesis.claims.stats`).

:func:`power_table` gives the other side: the probability of "reproduced" when the claim
is true, per seed count and true effect (in standard deviations of the per-seed
difference), for rules 4, 5 and 10, for chapter 6's "a configuration works / fails"
(:func:`thesis.claims.stats.judge_rate`, exact) at the seed counts chapter 6 runs,
:data:`RATE_SEED_COUNTS`, and for rule 6 on runs that fail (rule 3b) up to 40 seeds.

Laws (:data:`ALL_LAWS`): normal, exponential and Student t (2 df) (:data:`LAWS`);
failure mixtures, 10, 20 and 30 % of runs near 0.2 and the rest near 1.0
(:data:`FAILURE_LAWS`; the rules get each seed's failure flag, as a chapter passes its
own: fell, at chance, diverged), and the same mixtures without a flag
(:data:`BIMODAL_LAWS`, rules 4, 5, 6 and 9); discrete values, a count of 4 trials
(:data:`DISCRETE_LAWS`). Rule 7 (:func:`thesis.claims.stats.decide_within_budget`) is
simulated at a per-seed success rate of one half, and existence
(:func:`false_existence`) with no event and runs passing by chance at 1-5 %. :func:`false_not_reproduced_combined` calibrates a multi-part
claim's "not reproduced" (:func:`thesis.claims.stats.combine`). ``thesis check`` writes it to
``results/<profile>/claims_power.json`` and the report shows it in its method section.

Every simulation draws from a generator seeded by its arguments, so the tables are
deterministic. ``rules`` defaults to :mod:`thesis.claims.stats` and may be any module with
the same decision helpers (the calibration test runs it on another version of the rules
too).
"""

from __future__ import annotations

import inspect
import types
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize
from scipy import stats as sps

from thesis.claims import ch6, stats

#: Seed counts the rules are calibrated at (the profiles run 3 to 10 seeds).
SEED_COUNTS = (3, 5, 10)
#: Seed counts of chapter 6's rate rule (:func:`thesis.claims.stats.judge_rate`): the
#: profiles' chapter-6 seed counts (smoke 6, paper 10, default 40) and 20 between them.
RATE_SEED_COUNTS = (6, 10, 20, 40)
#: Root seed of every simulation here.
SEED = 20240601
#: Particles and generations of the simulated rule-9 runs (small: the per-seed effect is an
#: average over them, which only makes it closer to normal than the thesis's 20 x 13).
RUN_GENERATIONS = 5
RUN_PARTICLES = 10
#: True effects of the power table, in standard deviations of the per-seed difference.
EFFECTS = (0.5, 1.0, 2.0)
#: True event rates of rule 10's power rows.
RATES = (0.75, 0.9, 1.0)
#: True success rates of the rate rule's power rows: "works" 0.2, 0.4 and 0.6 above the
#: rate of a configuration that fails (:data:`thesis.claims.ch6.FAILS_RATE`), "fails" as
#: far below that of one that works (:data:`thesis.claims.ch6.WORKS_RATE`).
WORKS_RATES = (0.4, 0.6, 0.8)
FAILS_RATES = (0.4, 0.2, 0.0)
#: Failure rates of the power rows of rule 3b (runs that fail), and the seed counts they
#: are shown at (beyond the profiles' 3-10: how many seeds such a claim needs).
FAILURE_RATES = (0.1, 0.2, 0.3)
FAILURE_SEED_COUNTS = (3, 5, 10, 20, 40)
#: Bound of those rows' "the mean is above": below every mixture's mean (0.76-0.92).
FAILURE_POWER_BOUND = 0.6

#: Per-seed laws, as frozen scipy distributions: normal, skewed (exponential) and
#: heavy-tailed (Student t with 2 degrees of freedom: infinite variance).
LAWS: dict[str, sps.rv_continuous] = {
    "normal": sps.norm(),
    "exponential": sps.expon(),
    "t2": sps.t(2),
}


@dataclass(frozen=True)
class FailureMixture:
    """Per-seed law of runs that sometimes fail: a share ``rate`` of runs gives values
    near ``fail`` (normal, sd ``sd``), the rest near ``work``; a failed run's value is far
    from the rest (16 sd). ``declared`` is the range a chapter declares for a failed
    run's value (wider than the truth), passed to the rules as ``failure_bounds``.
    Units: the value's own (think of an accuracy in [0, 1])."""

    rate: float
    work: float = 1.0
    fail: float = 0.2
    sd: float = 0.05
    declared: tuple[float, float] = (0.0, 0.4)

    def mean(self) -> float:
        return (1.0 - self.rate) * self.work + self.rate * self.fail

    def cdf(self, x: float) -> float:
        return float((1.0 - self.rate) * sps.norm.cdf(x, self.work, self.sd)
                     + self.rate * sps.norm.cdf(x, self.fail, self.sd))

    def ppf(self, q: float) -> float:
        return float(optimize.brentq(lambda x: self.cdf(x) - q, self.fail - 10 * self.sd,
                                     self.work + 10 * self.sd, xtol=1e-12))

    def median(self) -> float:
        return self.ppf(0.5)

    def draw(self, rng: np.random.Generator, shape) -> tuple[np.ndarray, np.ndarray]:
        """(values, failed) of shape ``shape``."""
        failed = rng.random(shape) < self.rate
        x = np.where(failed, self.fail, self.work) + self.sd * rng.standard_normal(shape)
        return x, failed

    def rvs(self, size, random_state: np.random.Generator) -> np.ndarray:
        return self.draw(random_state, size)[0]


#: Laws of runs that fail: 10, 20 and 30 % of runs near 0.2, the rest near 1.0; the rules
#: get each seed's failure flag.
FAILURE_LAWS: dict[str, FailureMixture] = {
    f"fail{int(round(100 * r))}": FailureMixture(r) for r in (0.1, 0.2, 0.3)}
#: The same mixtures without a flag (a second mode the chapter does not record: a
#: classifier that stays at the majority share, a run that diverged or never improved):
#: the rules see the values alone.
BIMODAL_LAWS: dict[str, FailureMixture] = {
    f"bimodal{int(round(100 * r))}": FailureMixture(r) for r in (0.1, 0.2, 0.3)}
#: Both kinds of mixture.
MIXTURE_LAWS: dict[str, FailureMixture] = {**FAILURE_LAWS, **BIMODAL_LAWS}
#: Discrete per-seed values (a count of 4 trials: many ties, all seeds equal often):
#: symmetric (Binomial(4, 0.5)) and skewed (Binomial(4, 0.8)).
DISCRETE_LAWS: dict[str, sps.rv_discrete] = {
    "binomial4_half": sps.binom(4, 0.5),
    "binomial4_0.8": sps.binom(4, 0.8),
}
#: Every law of the calibration, by name.
ALL_LAWS = {**LAWS, **MIXTURE_LAWS, **DISCRETE_LAWS}
#: Rule 9's "not worse" null needs a continuous law (the shift to a given A12) or a
#: failure mixture (the two runs' failure rates apart by twice the margin).
NOT_WORSE_LAWS = (*LAWS, *MIXTURE_LAWS)


def _rng(*key: object) -> np.random.Generator:
    """Generator seeded by :data:`SEED` and ``key`` (stable across processes)."""
    return np.random.default_rng([SEED, zlib.crc32(repr(key).encode())])


def _draw(law: str, rng: np.random.Generator, shape) -> np.ndarray:
    """Draws of ``ALL_LAWS[law]`` of shape ``shape``, shifted to mean 0."""
    return _draw_failed(law, rng, shape)[0]


def _draw_failed(law: str, rng: np.random.Generator, shape) -> tuple[np.ndarray, np.ndarray]:
    """(draws shifted to mean 0, failed flags) of ``ALL_LAWS[law]``; no run fails
    outside :data:`MIXTURE_LAWS`."""
    dist = ALL_LAWS[law]
    if isinstance(dist, FailureMixture):
        x, failed = dist.draw(rng, shape)
        return x - dist.mean(), failed
    x = np.asarray(dist.rvs(size=shape, random_state=rng), float) - float(dist.mean())
    return x, np.zeros(np.shape(x), bool)


def _failure_kw(rules, fn: str, law: str, failed, bounds) -> dict:
    """``failed=`` and ``failure_bounds=`` for ``rules.<fn>`` under a failure law (the
    chapter knows its failure indicator; not under :data:`BIMODAL_LAWS`, whose second mode
    nobody flags), when ``rules`` takes them (a version of the rules without them, as the
    before-table's, runs without)."""
    if law not in FAILURE_LAWS or "failed" not in inspect.signature(
            getattr(rules, fn)).parameters:
        return {}
    return {"failed": failed, "failure_bounds": bounds}


def _discrete_kw(rules, fn: str, law: str) -> dict:
    """``discrete=True`` for ``rules.<fn>`` under a discrete law (the chapter knows its
    values are counts), when ``rules`` takes it."""
    if law not in DISCRETE_LAWS or "discrete" not in inspect.signature(
            getattr(rules, fn)).parameters:
        return {}
    return {"discrete": True}


def shift_for_a12(law: str, a12: float) -> float:
    """The shift d with P(X + d > Y) = ``a12`` for X, Y independent draws of ``law``."""
    dist = LAWS[law]

    def a(d: float) -> float:
        val, _ = integrate.quad(lambda y: dist.pdf(y) * dist.sf(y - d), -np.inf, np.inf,
                                limit=200)
        return val - a12

    return float(optimize.brentq(a, -20.0, 20.0, xtol=1e-10))


# ------------------------------------------------------------------ one null per rule
#: Equivalence margin of rule 5's null: 1 sd of the continuous and discrete laws, 0.1 in
#: the value units of a failure mixture (an accuracy, say).
MARGIN = 1.0
FAILURE_MARGIN = 0.1


def _partner(law: str, rng: np.random.Generator, n: int) -> np.ndarray:
    """Method B of rules 4 and 5 under a failure law: runs that never fail, normal about
    the mixture's mean (0 after the shift) with its within-component sd: "A beats B" with
    the same mean, A's runs sometimes failing (the issue's probe)."""
    return MIXTURE_LAWS[law].sd * rng.standard_normal(n)


def _difference_bounds(law: str, shift: float = 0.0) -> tuple[float, float]:
    """Declared range of A - B on a seed where A failed (B near the working value): a
    failed A loses at most the declared failure range's distance below a working run and
    gains at most its distance above a failed one."""
    d = MIXTURE_LAWS[law]
    return (d.declared[0] - d.work + shift, d.declared[1] - d.fail + shift)


def _null_beats(rules, law, n, rng):
    if law in MIXTURE_LAWS:
        a, fa = _draw_failed(law, rng, n)
        kw = _failure_kw(rules, "decide_beats", law, fa, _difference_bounds(law))
        return rules.decide_beats(a, _partner(law, rng, n), higher_is_better=True,
                                  **kw).status
    a, b = _draw(law, rng, n), _draw(law, rng, n)
    return rules.decide_beats(a, b, higher_is_better=True,
                              **_discrete_kw(rules, "decide_beats", law)).status


def _null_equivalent(rules, law, n, rng):
    # true difference exactly at the margin: A's per-seed values one margin above B's
    if law in MIXTURE_LAWS:
        m = FAILURE_MARGIN
        a, fa = _draw_failed(law, rng, n)
        kw = _failure_kw(rules, "decide_equivalent", law, fa, _difference_bounds(law, m))
        return rules.decide_equivalent(a + m - _partner(law, rng, n), margin=m, **kw).status
    a, b = _draw(law, rng, n) + MARGIN, _draw(law, rng, n)
    return rules.decide_equivalent(a - b, margin=MARGIN,
                                   **_discrete_kw(rules, "decide_equivalent", law)).status


def _null_threshold(below: bool):
    def null(rules, law, n, rng):
        # mean exactly at the bound; the law's skew (a mixture's failures) points down, so
        # for "below" it points towards the claimed side and for "above" away from it
        # (the continuous laws' skew points up: the other way round)
        x, failed = _draw_failed(law, rng, n)
        kw = _discrete_kw(rules, "decide_threshold", law)
        if law in MIXTURE_LAWS:
            d = MIXTURE_LAWS[law]
            kw = _failure_kw(rules, "decide_threshold", law, failed,
                             (d.declared[0] - d.mean(), d.declared[1] - d.mean()))
        return rules.decide_threshold(x, bound=0.0, below=below, **kw).status
    return null


def _null_censored(rules, law, n, rng):
    # both methods' true costs from one law; a run stops at the budget (the 70th
    # percentile of the cost) and then reports what it spent, right-censored. Under a
    # failure law the cost is minus the value: a failed run costs far more than the rest.
    sign = -1.0 if law in FAILURE_LAWS else 1.0
    dist = ALL_LAWS[law]
    q = 0.3 if sign < 0 else 0.7
    budget = float(sign * (dist.ppf(q) - dist.mean()))
    ca, cb = sign * _draw(law, rng, n), sign * _draw(law, rng, n)
    ad, bd = ca <= budget, cb <= budget
    return rules.decide_fewer_censored(np.minimum(ca, budget), ad, np.minimum(cb, budget),
                                       bd).status


def _failing_runs(law: str, rng: np.random.Generator, n: int, rate_a: float, rate_b: float):
    """(a, b, failed) particle scores (n, G, N) of two runs per seed under a failure law:
    a seed's run of A fails with probability ``rate_a`` (then every particle scores near
    the failure value), B's with ``rate_b``; ``failed``: either run of the seed failed."""
    d = MIXTURE_LAWS[law]
    shape = (n, RUN_GENERATIONS, RUN_PARTICLES)
    fa, fb = rng.random(n) < rate_a, rng.random(n) < rate_b
    a = np.where(fa[:, None, None], d.fail, d.work) + d.sd * rng.standard_normal(shape)
    b = np.where(fb[:, None, None], d.fail, d.work) + d.sd * rng.standard_normal(shape)
    return a, b, fa | fb


#: Declared range of rule 9's per-seed effect (A12 - 0.5) on a seed where a run failed.
EFFECT_BOUNDS = (-0.5, 0.5)


def _null_runs_better(rules, law, n, rng):
    if law in MIXTURE_LAWS:
        rate = MIXTURE_LAWS[law].rate
        a, b, failed = _failing_runs(law, rng, n, rate, rate)
        kw = _failure_kw(rules, "decide_runs_over_generations", law, failed, EFFECT_BOUNDS)
        return rules.decide_runs_over_generations(a, b, bound=stats.ALPHA, claim="better",
                                                  **kw).status
    shape = (n, RUN_GENERATIONS, RUN_PARTICLES)
    a, b = _draw(law, rng, shape), _draw(law, rng, shape)
    return rules.decide_runs_over_generations(a, b, bound=stats.ALPHA, claim="better").status


_SHIFTS: dict[str, float] = {}


def _null_not_worse(rules, law, n, rng):
    if law in MIXTURE_LAWS:
        # A's runs fail 2 x SMALL_A_EFFECT more often than B's: a seed where only A fails
        # has A12 = 0 (effect -0.5), only B +0.5, so the true mean effect is exactly
        # -SMALL_A_EFFECT (the runs' values are far apart; equal status: 0 on average)
        rate, e = MIXTURE_LAWS[law].rate, stats.SMALL_A_EFFECT
        a, b, failed = _failing_runs(law, rng, n, rate + e, rate - e)
        kw = _failure_kw(rules, "decide_not_worse", law, failed, EFFECT_BOUNDS)
        return rules.decide_not_worse(a, b, **kw).status
    # per-particle shift that makes the true A12 - 0.5 exactly -SMALL_A_EFFECT
    if law not in _SHIFTS:
        _SHIFTS[law] = shift_for_a12(law, 0.5 - stats.SMALL_A_EFFECT)
    shape = (n, RUN_GENERATIONS, RUN_PARTICLES)
    a, b = _draw(law, rng, shape) + _SHIFTS[law], _draw(law, rng, shape)
    return rules.decide_not_worse(a, b).status


def _null_majority(rules, law, n, rng):
    # the event occurs in exactly half the runs: the per-seed value is above its median
    x = _draw(law, rng, n)
    return rules.decide_majority(x > LAWS[law].median() - LAWS[law].mean()).status


def _null_within_budget(rules, law, n, rng):
    # rule 7 at a per-seed success rate of exactly one half: a seed reaches the target
    # within the budget when its value is above the law's median (every run long enough)
    x = _draw(law, rng, n)
    hit = x > LAWS[law].median() - LAWS[law].mean()
    budget = 100.0
    reached = np.where(hit, budget, np.nan)
    return rules.decide_within_budget(reached, np.full(n, 10 * budget), budget=budget,
                                      label="evaluations").status


#: rule name -> null simulator ``(rules, law, n, rng) -> status``.
NULLS: dict[str, Callable] = {
    "rule4_beats": _null_beats,
    "rule5_equivalent": _null_equivalent,
    "rule6_above": _null_threshold(below=False),
    "rule6_below": _null_threshold(below=True),
    "rule4_censored": _null_censored,
    "rule9_better": _null_runs_better,
    "rule9_not_worse": _null_not_worse,
    "rule10_majority": _null_majority,
    "rule7_within_budget": _null_within_budget,
}
#: The laws each rule's null is simulated under (rule 10's events are flags: the law only
#: decides which seeds show the event, exactly half of them).
RULE_LAWS: dict[str, tuple[str, ...]] = {
    **{r: (*LAWS, *FAILURE_LAWS, *DISCRETE_LAWS) for r in NULLS},
    **{r: (*LAWS, *MIXTURE_LAWS, *DISCRETE_LAWS) for r in (
        "rule4_beats", "rule5_equivalent", "rule6_above", "rule6_below", "rule9_better")},
    "rule9_not_worse": NOT_WORSE_LAWS,
    "rule10_majority": tuple(LAWS),
    "rule7_within_budget": tuple(LAWS),
}


def false_reproduced(rule: str, n: int, law: str, *, reps: int,
                     rules: types.ModuleType = stats) -> float:
    """Share of ``reps`` simulated nulls of ``rule`` (a key of :data:`NULLS`) with ``n``
    seeds and per-seed law ``law`` (a key of :data:`ALL_LAWS`) that ``rules`` calls
    "reproduced"."""
    if law not in RULE_LAWS[rule]:
        raise ValueError(f"{rule} is not simulated under {law!r}: {RULE_LAWS[rule]}")
    rng = _rng("null", rule, n, law)
    hits = sum(NULLS[rule](rules, law, n, rng) == "reproduced" for _ in range(reps))
    return hits / reps


#: Spurious per-run success rates of the false-existence calibration (a run passes the
#: success criterion by chance: an outcome drawn at the rounding level), and its seed
#: counts (the profiles' 3 to 10, and chapter 6's 40).
SPURIOUS_RATES = (0.01, 0.02, 0.05)
EXISTENCE_SEED_COUNTS = (3, 5, 10, 40)
#: True rates of a real event (its twin repeats it) of the existence power rows.
EXISTENCE_RATES = (0.1, 0.3, 0.5)


def false_existence(n: int, q: float, *, reps: int,
                    rules: types.ModuleType = stats) -> float:
    """Share of ``reps`` simulated claims that ``rules.decide_exists`` calls "reproduced"
    when no event exists: each of ``n`` seeds' runs passes the success criterion by chance
    with probability ``q``, its perturbed twin independently so; the twin's flags go in
    as ``replicated`` where the rules take them (the before-table's rules do not)."""
    rng = _rng("exists", n, q)
    takes = "replicated" in inspect.signature(rules.decide_exists).parameters
    hits = 0
    for _ in range(reps):
        run, twin = rng.random(n) < q, rng.random(n) < q
        kw = {"replicated": twin.astype(float)} if takes else {}
        hits += rules.decide_exists(run.astype(float), **kw).status == "reproduced"
    return hits / reps


def existence_table(*, reps: int, rules: types.ModuleType = stats,
                    ns: Sequence[int] = EXISTENCE_SEED_COUNTS,
                    qs: Sequence[float] = SPURIOUS_RATES) -> list[dict]:
    """False-existence rate per seed count and spurious per-run rate
    (:func:`false_existence`): rows ``{"rule", "n_seeds", "law", "rate", "reps",
    "nominal"}``."""
    return [{"rule": "rule10_exists", "n_seeds": n, "law": f"spurious{q:g}", "reps": reps,
             "nominal": stats.ONE_SIDED, "rate": false_existence(n, q, reps=reps, rules=rules)}
            for n in ns for q in qs]


def monte_carlo_bound(level: float, reps: int, k: float = 3.0) -> float:
    """``level`` plus ``k`` binomial standard errors of a rate estimated from ``reps``."""
    return level + k * np.sqrt(level * (1 - level) / reps)


def calibration_table(*, reps: int, rules: types.ModuleType = stats,
                      rule_names: Sequence[str] = tuple(NULLS),
                      ns: Sequence[int] = SEED_COUNTS,
                      laws: Sequence[str] | None = None) -> list[dict]:
    """False-"reproduced" rate per rule, seed count and law (every law of
    :data:`RULE_LAWS` unless ``laws``): a list of ``{"rule", "n_seeds", "law", "rate",
    "reps", "nominal"}``."""
    return [{"rule": r, "n_seeds": n, "law": law, "reps": reps, "nominal": stats.ONE_SIDED,
             "rate": false_reproduced(r, n, law, reps=reps, rules=rules)}
            for r in rule_names for n in ns for law in RULE_LAWS[r]
            if laws is None or law in laws]


def false_not_reproduced_combined(parts: int, n: int, *, reps: int,
                                  rules: types.ModuleType = stats) -> float:
    """Share of ``reps`` claims of ``parts`` parts, each rule 6 ("above") with normal
    per-seed values whose mean lies exactly at the bound (every part true at the
    boundary), that ``rules.combine`` calls "not_reproduced" with ``n`` seeds per part:
    the false-"not reproduced" rate of a multi-part claim (``ch5.rc_touch_best_overall``
    has 15 parts)."""
    rng = _rng("combine", parts, n)
    hits = 0
    for _ in range(reps):
        x = rng.standard_normal((parts, n))
        v = rules.combine({f"p{i}": rules.decide_threshold(r, bound=0.0, below=False)
                           for i, r in enumerate(x)})
        hits += v.status == "not_reproduced"
    return hits / reps


# ------------------------------------------------------------------ power
def _power_beats(n: int, effect: float, reps: int) -> float:
    rng = _rng("power", "rule4", n, effect)
    d = rng.normal(effect, 1.0, (reps, n))
    return float(np.mean([stats.decide_beats(x, np.zeros(n), higher_is_better=True).status
                          == "reproduced" for x in d]))


def _power_equivalent(n: int, margin: float, reps: int) -> float:
    rng = _rng("power", "rule5", n, margin)
    d = rng.normal(0.0, 1.0, (reps, n))
    return float(np.mean([stats.decide_equivalent(x, margin=margin).status == "reproduced"
                          for x in d]))


def _power_failing(n: int, rate: float, reps: int) -> float:
    """Rule 6 ("the mean is above :data:`FAILURE_POWER_BOUND`") with its failure indicator
    (rule 3b) when a share ``rate`` of runs fails (:class:`FailureMixture`, declared
    failure range [0, 0.4]): the probability of "reproduced" with ``n`` seeds."""
    law = FailureMixture(rate)
    rng = _rng("power", "rule3b", n, rate)
    hits = 0
    for _ in range(reps):
        x, failed = law.draw(rng, n)
        hits += stats.decide_threshold(x, bound=FAILURE_POWER_BOUND, below=False,
                                       failed=failed, failure_bounds=law.declared
                                       ).status == "reproduced"
    return hits / reps


def _count_probability(n: int, rate: float, says: Callable[[int], bool]) -> float:
    """Exact: the binomial probability, ``n`` seeds at true rate ``rate``, of the counts
    ``k`` of successes for which ``says(k)`` holds."""
    ks = [k for k in range(n + 1) if says(k)]
    return float(sps.binom.pmf(ks, n, rate).sum())


def _power_majority(n: int, rate: float) -> float:
    """Exact: the probability that rule 10 reproduces with ``n`` seeds at event rate
    ``rate``."""
    return _count_probability(n, rate, lambda k: stats.decide_majority(
        [1.0] * k + [0.0] * (n - k)).status == "reproduced")


def rate_verdict_probability(n: int, rate: float, judged: str) -> float:
    """Exact: the probability that chapter 6's rate rule (:func:`thesis.claims.ch6.judge`)
    says ``judged`` ("works", "fails" or "unclear") for ``n`` seeds whose true success
    rate is ``rate``."""
    return _count_probability(n, rate, lambda k: ch6.judge(k / n, n) == judged)


def power_table(*, reps: int = 1000, ns: Sequence[int] = SEED_COUNTS,
                effects: Sequence[float] = EFFECTS, rates: Sequence[float] = RATES,
                rate_ns: Sequence[int] = RATE_SEED_COUNTS,
                works_rates: Sequence[float] = WORKS_RATES,
                fails_rates: Sequence[float] = FAILS_RATES,
                failure_rates: Sequence[float] = FAILURE_RATES,
                failure_ns: Sequence[int] = FAILURE_SEED_COUNTS,
                existence_ns: Sequence[int] = EXISTENCE_SEED_COUNTS,
                spurious_rates: Sequence[float] = SPURIOUS_RATES,
                existence_rates: Sequence[float] = EXISTENCE_RATES) -> dict:
    """Probability of "reproduced" when the claim holds, per seed count (deterministic).

    Returns ``{"nominal": ..., "reps": ..., "rows": [...]}``; each row has ``rule``,
    ``n_seeds``, ``effect`` (what is true, in words and number) and ``power``:

    - rule 4 ("A beats B"): normal per-seed differences with mean ``effect`` sd;
    - rule 5 ("A is like B"): true difference 0, margin ``effect`` sd;
    - rule 10 ("in most runs"): event rate ``rate`` (exact binomial sum);
    - chapter 6's rate rule at ``rate_ns`` seeds (exact): "a configuration works" at
      true success rates ``works_rates``, "a configuration fails" at ``fails_rates``;
    - rule 6 with a failure indicator (rule 3b) at ``failure_ns`` seeds: a share
      ``failure_rates`` of runs fails (value near 0.2, declared range [0, 0.4]), the rest
      near 1.0; the claim "the mean is above :data:`FAILURE_POWER_BOUND`" is true.
    - rule 10's existence at ``existence_ns`` seeds (exact): "reproduced" when no event
      exists and runs pass by chance at ``spurious_rates`` (their twins independently:
      the false-existence rate, rule ``rule10_exists_spurious``), and when a real event
      shows in a share ``existence_rates`` of seeds and its twin repeats it.
    Rule 6 without failures has rule 4's power (one-sided t on the values minus the bound).
    """
    rows = []
    for n in ns:
        for e in effects:
            rows.append({"rule": "rule4_beats", "n_seeds": n, "effect": e,
                         "truth": f"advantage of {e:g} sd", "power": _power_beats(n, e, reps)})
        for e in effects:
            rows.append({"rule": "rule5_equivalent", "n_seeds": n, "effect": e,
                         "truth": f"no difference, margin {e:g} sd",
                         "power": _power_equivalent(n, e, reps)})
        for r in rates:
            rows.append({"rule": "rule10_majority", "n_seeds": n, "effect": r,
                         "truth": f"event rate {r:g}", "power": _power_majority(n, r)})
    for n in rate_ns:
        for r in works_rates:
            rows.append({"rule": "rate_works", "n_seeds": n, "effect": r,
                         "truth": f"success rate {r:g}",
                         "power": rate_verdict_probability(n, r, "works")})
        for r in fails_rates:
            rows.append({"rule": "rate_fails", "n_seeds": n, "effect": r,
                         "truth": f"success rate {r:g}",
                         "power": rate_verdict_probability(n, r, "fails")})
    for n in failure_ns:
        for r in failure_rates:
            mean = FailureMixture(r).mean()
            rows.append({"rule": "rule6_failing_runs", "n_seeds": n, "effect": r,
                         "truth": f"{100 * r:g} % of runs fail (mean {mean:.2f}, bound "
                                  f"{FAILURE_POWER_BOUND:g})",
                         "power": _power_failing(n, r, reps)})
    for n in existence_ns:
        need = stats.exists_needs(n, replicated=True)
        for q in spurious_rates:
            rows.append({"rule": "rule10_exists_spurious", "n_seeds": n, "effect": q,
                         "truth": f"no event; runs pass by chance at {q:g} (twins too)",
                         "power": float(sps.binom.sf(need - 1, n, q * q))})
        for r in existence_rates:
            rows.append({"rule": "rule10_exists", "n_seeds": n, "effect": r,
                         "truth": f"event in a share {r:g} of seeds, repeated by its twin",
                         "power": float(sps.binom.sf(need - 1, n, r))})
    return {"nominal": stats.ONE_SIDED, "reps": reps, "seed": SEED,
            "interval": stats.INTERVAL_METHOD, "rows": rows}


# ------------------------------------------------------------------ choosing the interval
def _claims_t(x: np.ndarray) -> np.ndarray:
    """(reps,) whether the Student t interval of each row of ``x`` lies above 0."""
    return np.array([stats.mean_interval(r).low > 0 for r in x])


def _claims_bootstrap(method: str):
    def claims(x: np.ndarray) -> np.ndarray:
        out = []
        for r in x:
            ci = stats.bootstrap_mean(r)
            if method == "percentile" and ci.method == "BCa":
                ci = _percentile(r)
            out.append(ci.low > 0)
        return np.array(out)
    return claims


def _percentile(r: np.ndarray) -> stats.Interval:
    res = sps.bootstrap((r,), np.mean, confidence_level=stats.CONFIDENCE,
                        n_resamples=stats.N_RESAMPLES, method="percentile",
                        rng=np.random.default_rng(stats.BOOTSTRAP_SEED))
    ci = res.confidence_interval
    return stats.Interval(float(r.mean()), float(ci.low), float(ci.high), r.size, "percentile")


def _claims_sign_flip(x: np.ndarray) -> np.ndarray:
    """Exact sign-flip permutation test of the mean (all 2^n sign patterns), one-sided."""
    n = x.shape[1]
    signs = 1 - 2 * ((np.arange(2 ** n)[:, None] >> np.arange(n)) & 1)  # (2^n, n)
    perm = signs @ x.T  # (2^n, reps) sums under every sign pattern
    p = (perm >= x.sum(axis=1)[None, :] - 1e-12).mean(axis=0)
    return p <= stats.ONE_SIDED


def _claims_wilcoxon(x: np.ndarray) -> np.ndarray:
    """Exact one-sided Wilcoxon signed-rank test (scipy, vectorised over rows)."""
    p = sps.wilcoxon(x, alternative="greater", axis=1, method="exact").pvalue
    return np.asarray(p) <= stats.ONE_SIDED


#: Candidate intervals/tests of rules 3-6: name -> (reps, n) values -> (reps,) "reproduced".
CANDIDATES: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "bootstrap_bca": _claims_bootstrap("BCa"),
    "bootstrap_percentile": _claims_bootstrap("percentile"),
    "student_t": _claims_t,
    "sign_flip": _claims_sign_flip,
    "wilcoxon": _claims_wilcoxon,
}


def _candidate_nulls(law: str, n: int, reps: int) -> dict[str, np.ndarray]:
    """(reps, n) per-seed values of the nulls the candidates are judged on: rule 4's
    paired differences of two draws of one law, and rule 6's values of the law with the
    mean at the bound, skew pointing towards and away from the claimed side."""
    rng = _rng("candidates", law, n)
    x = _draw(law, rng, (reps, n))
    return {"rule4_paired": _draw(law, rng, (reps, n)) - _draw(law, rng, (reps, n)),
            "rule6_skew_towards": x, "rule6_skew_away": -x}


def compare_candidates(*, reps: int, candidates: Sequence[str] = tuple(CANDIDATES),
                       ns: Sequence[int] = SEED_COUNTS,
                       laws: Sequence[str] = tuple(LAWS)) -> list[dict]:
    """False-"reproduced" rate of every candidate under each null, per seed count and
    law, and its power with normal differences of 1 sd: rows ``{"candidate", "null",
    "n_seeds", "law", "rate"}`` (``null`` ``"power_1sd"`` for the power rows)."""
    rows = []
    for n in ns:
        power_x = _rng("candidates", "power", n).normal(1.0, 1.0, (reps, n))
        for c in candidates:
            fn = CANDIDATES[c]
            for law in laws:
                for null, x in _candidate_nulls(law, n, reps).items():
                    rows.append({"candidate": c, "null": null, "n_seeds": n, "law": law,
                                 "rate": float(fn(x).mean())})
            rows.append({"candidate": c, "null": "power_1sd", "n_seeds": n, "law": "normal",
                         "rate": float(fn(power_x).mean())})
    return rows


def choose_candidate(rows: list[dict], reps: int, *,
                     nulls: Sequence[str] = ("rule4_paired",)) -> str:
    """The candidate with the highest mean power (``power_1sd`` rows) among those whose
    false rate stays within :func:`monte_carlo_bound` of :data:`stats.ONE_SIDED` under
    every ``nulls`` row (every seed count and law); ValueError when none does."""
    bound = monte_carlo_bound(stats.ONE_SIDED, reps)
    names = sorted({r["candidate"] for r in rows})
    ok = [c for c in names if all(r["rate"] <= bound for r in rows
                                  if r["candidate"] == c and r["null"] in nulls)]
    if not ok:
        raise ValueError("no candidate is calibrated")
    power = {c: np.mean([r["rate"] for r in rows
                         if r["candidate"] == c and r["null"] == "power_1sd"]) for c in ok}
    return max(ok, key=lambda c: power[c])
