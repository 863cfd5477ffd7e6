"""Calibration of the decision rules: under each rule's null, "reproduced" at most at the
nominal one-sided 2.5 % (plus three Monte-Carlo standard errors), at 3, 5 and 10 seeds,
with normal, exponential and Student-t (2 df) per-seed laws, failure mixtures (10-30 % of
runs failed, far from the rest; the rules get each seed's failure flag) and discrete
values (:mod:`thesis.claims.calibration`). The rule-6 cases that no interval of a mean can
hold at these seed counts (a law skewed away from the claimed side) are kept as strict
xfails, so the limit stays visible and a change that hides it fails."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats as sps

from thesis.claims import calibration as C
from thesis.claims import ch6, stats
from thesis.config import load_config

#: Simulated nulls per cell: enough for a 3-SE bound of 4 % at the 2.5 % level, cheap
#: enough for the whole module to stay within ~30 s of CPU.
REPS = 800
#: Rule 9 simulates whole runs per seed: fewer repetitions, a wider bound.
REPS_RUNS = 250

#: Rules whose level no rule of the values alone can hold under a second mode nobody flags
#: (a share of seeds far below the rest): rule 4 and rule 6 "above" say "reproduced" in
#: 10-45 % of draws at 3-10 seeds (test below); a chapter whose runs can fail passes its
#: failure indicator (rule 3b), which the FAILURE_LAWS cells calibrate. Rule 9 "not worse"
#: (whose runs carry no flag beyond a fall) instead says "reproduced" only from
#: NOT_WORSE_UNFLAGGED_MIN_SEEDS seeds on, so its bimodal cells are calibrated here.
UNFLAGGED_LIMIT = {"rule4_beats", "rule6_above"}
CELLS = [(rule, n, law) for rule in C.NULLS for n in C.SEED_COUNTS for law in C.RULE_LAWS[rule]
         if not (law in C.BIMODAL_LAWS and rule in UNFLAGGED_LIMIT)]
#: Rule 6 with an exponential law whose long tail points away from the claimed side:
#: about 10 % at every seed count for the t interval, and for any interval of a mean;
#: and with 5 and 10 seeds of a discrete law skewed away from it (a count of 4 trials at
#: 0.8: seeds at the top and one a step below pass "above the mean"), about 8 % and 5 %
#: (at 3 seeds such samples are ties, which discrete=True keeps from deciding).
KNOWN_LIMIT = {("rule6_below", n, "exponential") for n in C.SEED_COUNTS} | {
    ("rule6_above", n, "binomial4_0.8") for n in (5, 10)}
#: The failure mixtures with every rule they apply to: the cells that decide rule 3b.
FAILURE_CELLS = [c for c in CELLS if c[2] in C.FAILURE_LAWS]


def _reps(rule: str) -> int:
    return REPS_RUNS if rule.startswith("rule9") else REPS


@pytest.mark.parametrize("rule,n,law", [
    pytest.param(*c, marks=pytest.mark.xfail(
        strict=True, reason="rule 6's stated assumption: no per-seed law strongly skewed "
                            "away from the claimed side (Bahadur-Savage)"))
    if c in KNOWN_LIMIT else c for c in CELLS])
def test_false_reproduced_rate_within_nominal(rule, n, law):
    reps = _reps(rule)
    rate = C.false_reproduced(rule, n, law, reps=reps)
    assert rate <= C.monte_carlo_bound(stats.ONE_SIDED, reps), (rule, n, law, rate)


def test_unflagged_not_worse_decides_only_where_its_interval_holds(monkeypatch):
    """Rule 9's "not worse" on runs without a failure flag: its t interval alone says "not
    worse" in about 12 % of null draws at 5 seeds with 10 % of seeds at a second mode; it
    holds the level at NOT_WORSE_UNFLAGGED_MIN_SEEDS (40) under every bimodal law, where
    the rule starts deciding (below, the bimodal cells of the table above hold: 0 %)."""
    from thesis.claims.rules import runs

    reps = REPS_RUNS
    bound = C.monte_carlo_bound(stats.ONE_SIDED, reps)
    need = runs.NOT_WORSE_UNFLAGGED_MIN_SEEDS
    for law in C.BIMODAL_LAWS:
        assert C.false_reproduced("rule9_not_worse", need, law, reps=reps) <= bound, law
    monkeypatch.setattr(runs, "NOT_WORSE_UNFLAGGED_MIN_SEEDS", 0)
    assert C.false_reproduced("rule9_not_worse", 5, "bimodal10", reps=reps) > bound


@pytest.mark.parametrize("rule,law", [("rule4_beats", "bimodal20"), ("rule6_above", "bimodal10")])
def test_a_second_mode_nobody_flags_breaks_the_t_interval(rule, law):
    """A share of seeds at a second mode far below the rest, without a flag (a classifier
    at the majority share, a run that diverged): at 5 seeds "reproduced" in about 33 %
    (rule 4) and 45 % (rule 6 above) of draws under the null. No
    interval of the values alone holds there (3 or 5 seeds often see no second mode), so
    the claims whose runs can fail pass their failure indicator; with it (the fail* laws)
    every cell holds."""
    reps = _reps(rule)
    assert C.false_reproduced(rule, 5, law, reps=reps) > C.monte_carlo_bound(
        stats.ONE_SIDED, reps)
    flagged = law.replace("bimodal", "fail")
    assert C.false_reproduced(rule, 5, flagged, reps=reps) <= C.monte_carlo_bound(
        stats.ONE_SIDED, reps)


@pytest.mark.parametrize("n", C.EXISTENCE_SEED_COUNTS)
def test_existence_needs_events_that_repeat(n):
    """No event exists; every run passes the success criterion by chance at 1, 2 or 5 %,
    its perturbed twin independently so. Existence from one seed said "it happened" in
    34-87 % of draws at 40 seeds; counting only events the twin repeats, against runs
    passing by chance, at most 2.5 % (+ 3 MC SE), and exactly (binomial) at most 2.5 %."""
    for q in C.SPURIOUS_RATES:
        rate = C.false_existence(n, q, reps=REPS)
        assert rate <= C.monte_carlo_bound(stats.ONE_SIDED, REPS), (n, q, rate)
        need = stats.exists_needs(n, replicated=True)
        assert sps.binom.sf(need - 1, n, q * q) <= stats.ONE_SIDED
        assert sps.binom.sf(stats.exists_needs(n, replicated=False) - 1, n, q) <= (
            stats.ONE_SIDED)


def test_the_power_table_shows_existence_and_false_existence():
    rows = {(r["rule"], r["n_seeds"], r["effect"]): r["power"]
            for r in C.power_table(reps=10, ns=(), rate_ns=(), failure_ns=())["rows"]}
    for n in C.EXISTENCE_SEED_COUNTS:
        for q in C.SPURIOUS_RATES:
            assert rows[("rule10_exists_spurious", n, q)] <= stats.ONE_SIDED
    assert rows[("rule10_exists", 40, 0.3)] > 0.99 and rows[("rule10_exists", 3, 0.1)] < 0.3


def test_runs_that_fail_cannot_pass_on_the_seeds_that_saw_no_failure():
    """The issue's probe: 80 % of runs near 1.0, 20 % near 0.2 (mean 0.84). The t interval
    of 3 seeds that saw no failure (half the time) trusts them: "above 0.84" from
    (1.0, 0.98, 1.02). With the failure flags (rule 3b) the unseen failure rate (up to
    77 % at 3 seeds) keeps the interval wide: inconclusive."""
    x = [1.0, 0.98, 1.02]
    assert stats.decide_threshold(x, bound=0.84, below=False).status == "reproduced"
    v = stats.decide_threshold(x, bound=0.84, below=False, failed=[0, 0, 0],
                               failure_bounds=(0.0, 0.4))
    assert v.status == "inconclusive" and v.measured["value_ci_low"] < 0.84
    # without a declared range of a failed run's value nothing bounds the unseen failures
    v = stats.decide_beats(x, [0.84] * 3, higher_is_better=True, failed=[0, 0, 0])
    assert v.status == "inconclusive" and v.measured["advantage_ci_low"] == -np.inf


def test_a_tie_of_fewer_than_six_seeds_of_discrete_values_decides_nothing():
    """All seeds equal: a discrete law's tie, not a law without spread (the skewed count
    of 4 trials ties at its top in 0.41^3 = 7 % of 3-seed samples). Values not declared
    discrete keep the zero-width interval."""
    for n in (3, 5):
        v = stats.decide_threshold([4.0] * n, bound=3.2, below=False, discrete=True)
        assert v.status == "inconclusive" and "same value" in v.detail
        assert stats.decide_threshold([4.0] * n, bound=3.2, below=False).status == (
            "reproduced")
    assert stats.decide_threshold([4.0] * 6, bound=3.2, below=False,
                                  discrete=True).status == "reproduced"
    assert stats.TIE_MIN_SEEDS == 6 and 2.0 ** -6 <= stats.ONE_SIDED < 2.0 ** -5
    assert C.false_reproduced("rule6_below", 3, "binomial4_0.8", reps=REPS) <= (
        C.monte_carlo_bound(stats.ONE_SIDED, REPS))


@pytest.mark.parametrize("n", C.SEED_COUNTS)
def test_a_claim_of_many_parts_is_not_contradicted_by_chance(n):
    """15 parts each true at its boundary (ch5.rc_touch_best_overall's size): "not
    reproduced" at most 2.5 % (+ 3 MC SE) with Holm over the parts; about 1 - 0.975^15 =
    32 % when any part's own "not reproduced" counted."""
    rate = C.false_not_reproduced_combined(15, n, reps=REPS)
    assert rate <= C.monte_carlo_bound(stats.ONE_SIDED, REPS), rate


def test_combine_needs_a_part_contradicted_at_the_family_level():
    bad = stats.decide_threshold([-1.0, -1.2, -0.8, -1.1], bound=0.0, below=False)
    p = bad.measured["p_not_reproduced"]
    assert bad.status == "not_reproduced" and 0 < p < stats.ONE_SIDED / 15
    ok = stats.decide_threshold([1.0, 1.2, 0.8, 1.1], bound=0.0, below=False)
    assert stats.combine({"a": ok, "b": bad}).status == "not_reproduced"
    weak = stats.decide_threshold([-0.3, -0.1, -0.5, -0.3, -0.2], bound=0.0, below=False)
    assert weak.status == "not_reproduced"
    assert weak.measured["p_not_reproduced"] > stats.ONE_SIDED / 15
    many = {f"p{i}": ok for i in range(14)} | {"weak": weak}
    v = stats.combine(many)
    assert v.status == "inconclusive" and "family level" in v.detail
    # a not-reproduced part with no p (a check's own logic) still contradicts the whole
    from thesis.claims.types import Verdict
    assert stats.combine({"a": ok, "n": Verdict("not_reproduced")}).status == "not_reproduced"
    # the p of the mixture interval comes from the same interval (bisection)
    x = np.array([0.1, 0.12, 0.09, 0.11, 0.1, 0.08, 0.1, 0.13, 0.1, 0.11])
    v = stats.decide_threshold(x, bound=0.5, below=False, failed=np.zeros(10),
                               failure_bounds=(0.0, 0.4))
    assert v.status == "not_reproduced" and 0 < v.measured["p_not_reproduced"] < 1e-3


def test_the_bootstrap_interval_used_before_is_not_calibrated():
    """The interval the rules used before (BCa bootstrap): "A beats B" far too often at
    3 seeds under no difference, where the t interval holds the level."""
    x = C._candidate_nulls("normal", 3, 400)["rule4_paired"]
    before = C.CANDIDATES["bootstrap_bca"](x).mean()
    now = C.CANDIDATES["student_t"](x).mean()
    assert before > C.monte_carlo_bound(stats.ONE_SIDED, 400) >= now


def test_sign_flip_and_wilcoxon_cannot_reach_the_level_below_six_seeds():
    for n in (3, 5):
        x = np.full((1, n), 1.0)  # every seed in the claimed direction: the smallest p
        assert not C.CANDIDATES["sign_flip"](x).any()
        assert not C.CANDIDATES["wilcoxon"](x).any()
    assert C.CANDIDATES["sign_flip"](np.full((1, 6), 1.0)).all()


def test_the_t_interval_is_the_chosen_candidate():
    """The choice rule (the most powerful candidate calibrated under rule 4's null at every
    seed count and law) picks the t interval among the fast candidates."""
    rows = C.compare_candidates(reps=300, candidates=("student_t", "sign_flip", "wilcoxon"))
    assert C.choose_candidate(rows, 300) == "student_t"
    assert stats.INTERVAL_METHOD == "Student t"


def test_works_rule_of_chapter_6_is_calibrated_exactly():
    """A configuration that fails (success rate FAILS_RATE) is called "works" at most
    2.5 % of the time, and one that works (WORKS_RATE) is called "fails" as rarely, at
    every seed count chapter 6 runs."""
    for n in sorted(set(C.SEED_COUNTS) | set(C.RATE_SEED_COUNTS)):
        works = [k for k in range(n + 1) if ch6.judge(k / n, n) == "works"]
        fails = [k for k in range(n + 1) if ch6.judge(k / n, n) == "fails"]
        assert sum(sps.binom.pmf(works, n, ch6.FAILS_RATE)) <= stats.ONE_SIDED
        assert sum(sps.binom.pmf(fails, n, ch6.WORKS_RATE)) <= stats.ONE_SIDED
        assert C.rate_verdict_probability(n, ch6.FAILS_RATE, "works") == pytest.approx(
            sum(sps.binom.pmf(works, n, ch6.FAILS_RATE)))


@pytest.mark.parametrize("profile", ["smoke", "default", "paper"])
def test_the_rate_rule_is_calibrated_at_every_profiles_chapter_6_seed_count(profile):
    """Chapter 6's seed count in each profile is one the rate rule's calibration and power
    rows cover (a profile that changes it must extend RATE_SEED_COUNTS)."""
    n = len(load_config(profile)["ch6"]["seeds"])
    assert n in C.RATE_SEED_COUNTS, (profile, n, C.RATE_SEED_COUNTS)


def test_the_rate_rule_power_rows_at_the_default_seed_count():
    """At 40 seeds (the default profile), a true success rate of 0.6 is called "works"
    almost surely and 0.2 "fails"; counts of 14-17 of 40, which both tests reject (a rate
    between 0.2 and 0.6), are unclear, so a rate of 0.34 is no longer a coin flip between
    "works" (51 % before) and "fails" (49 %)."""
    rows = {(r["rule"], r["n_seeds"], r["effect"]): r["power"]
            for r in C.power_table(reps=10, ns=(), rate_ns=(40,), failure_ns=())["rows"]}
    assert rows[("rate_works", 40, 0.6)] > 0.95
    assert rows[("rate_fails", 40, 0.2)] > 0.95
    assert rows[("rate_fails", 40, 0.0)] == pytest.approx(1.0)
    assert rows[("rate_fails", 40, 0.4)] < rows[("rate_fails", 40, 0.2)]
    kw = dict(works_rate=ch6.WORKS_RATE, fails_rate=ch6.FAILS_RATE)
    assert stats.judge_rate(13, 40, **kw) == "fails"
    assert [stats.judge_rate(k, 40, **kw) for k in (14, 15, 16, 17)] == ["unclear"] * 4
    assert stats.judge_rate(18, 40, **kw) == "works"
    works, fails = (C.rate_verdict_probability(40, 0.34, j) for j in ("works", "fails"))
    unclear = C.rate_verdict_probability(40, 0.34, "unclear")
    assert works + fails + unclear == pytest.approx(1.0)
    assert works < 0.2 and unclear > 0.25


def test_the_power_table_shows_how_many_seeds_runs_that_fail_need():
    """Rule 3b's power rows: none at 3 and 5 seeds (the unseen failure rate is too
    wide), growing with seeds and falling with the failure rate."""
    rows = {(r["n_seeds"], r["effect"]): r["power"]
            for r in C.power_table(reps=200, ns=(), rate_ns=())["rows"]
            if r["rule"] == "rule6_failing_runs"}
    assert {n for n, _ in rows} == set(C.FAILURE_SEED_COUNTS)
    assert rows[(3, 0.1)] == rows[(5, 0.1)] == 0.0
    assert rows[(10, 0.1)] < rows[(40, 0.1)]
    assert rows[(40, 0.3)] < rows[(40, 0.1)]


def test_holm_over_seven_configurations_holds_the_family_level():
    """decide_any over 7 configurations all exactly at the bound: "some configuration
    holds" at most 2.5 % of the time (without the correction: about 1 - 0.975^7 = 16 %)."""
    rng = np.random.default_rng(7)
    reps, n = REPS, 5
    hits = 0
    for _ in range(reps):
        groups = {f"h{i}": rng.normal(0.0, 1.0, n) for i in range(7)}
        hits += stats.decide_any(groups, bound=0.0, below=False).status == "reproduced"
    assert hits / reps <= C.monte_carlo_bound(stats.ONE_SIDED, reps)


def test_power_table_is_deterministic_and_grows_with_effect_and_seeds():
    kw = dict(ns=(3, 10), effects=(0.5, 2.0), rates=(0.9,), failure_ns=(10,))
    a = C.power_table(reps=200, **kw)
    assert a == C.power_table(reps=200, **kw)
    p = {(r["rule"], r["n_seeds"], r["effect"]): r["power"] for r in a["rows"]}
    assert p[("rule4_beats", 3, 0.5)] < p[("rule4_beats", 3, 2.0)]
    assert p[("rule4_beats", 3, 2.0)] < p[("rule4_beats", 10, 2.0)]
    assert p[("rule5_equivalent", 10, 0.5)] < p[("rule5_equivalent", 10, 2.0)]
    assert p[("rule10_majority", 3, 0.9)] == 0.0  # 3 seeds cannot show a majority
    assert p[("rule10_majority", 10, 0.9)] == pytest.approx(
        sps.binom.sf(8, 10, 0.9))  # 9 or 10 of 10
    assert a["nominal"] == stats.ONE_SIDED and a["interval"] == "Student t"


def test_the_report_names_the_rows_of_runs_that_fail():
    from thesis.report import verdicts as V

    power = C.power_table(reps=20, ns=(), rate_ns=(), failure_ns=(3, 40), failure_rates=(0.1,))
    page = V.method_html(power)
    assert "X above a bound, runs that fail (rule 3b)" in page
    assert "10 % of runs fail (mean 0.92, bound 0.6)" in page and "40 seeds" in page
