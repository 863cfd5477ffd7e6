"""Calibration of the decision rules: under each rule's null, "reproduced" at most at the
nominal one-sided 2.5 % (plus three Monte-Carlo standard errors), at 3, 5 and 10 seeds,
with normal, exponential and Student-t (2 df) per-seed laws
(:mod:`thesis.claims.calibration`). The rule-6 case that no interval of a mean can hold
at these seed counts (a law skewed away from the claimed side) is kept as a strict xfail,
so the limit stays visible and a change that hides it fails."""

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

CELLS = [(rule, n, law) for rule in C.NULLS for n in C.SEED_COUNTS for law in C.LAWS]
#: Rule 6 with an exponential law whose long tail points away from the claimed side:
#: about 10 % at every seed count for the t interval, and for any interval of a mean.
KNOWN_LIMIT = {("rule6_below", n, "exponential") for n in C.SEED_COUNTS}


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
    almost surely, and 0.4 most of the time; a "fails" needs a rate well below 0.4, as
    counts of 14-17 of 40 are read as "works" (judge_rate's overlap)."""
    rows = {(r["rule"], r["n_seeds"], r["effect"]): r["power"]
            for r in C.power_table(reps=10, ns=(), rate_ns=(40,))["rows"]}
    assert rows[("rate_works", 40, 0.6)] > 0.99
    assert 0.5 < rows[("rate_works", 40, 0.4)] < 0.95
    assert rows[("rate_fails", 40, 0.0)] == pytest.approx(1.0)
    assert rows[("rate_fails", 40, 0.4)] < rows[("rate_fails", 40, 0.2)]
    assert stats.judge_rate(14, 40, works_rate=ch6.WORKS_RATE,
                            fails_rate=ch6.FAILS_RATE) == "works"
    assert stats.judge_rate(13, 40, works_rate=ch6.WORKS_RATE,
                            fails_rate=ch6.FAILS_RATE) == "fails"


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
    a = C.power_table(reps=200, ns=(3, 10), effects=(0.5, 2.0), rates=(0.9,))
    assert a == C.power_table(reps=200, ns=(3, 10), effects=(0.5, 2.0), rates=(0.9,))
    p = {(r["rule"], r["n_seeds"], r["effect"]): r["power"] for r in a["rows"]}
    assert p[("rule4_beats", 3, 0.5)] < p[("rule4_beats", 3, 2.0)]
    assert p[("rule4_beats", 3, 2.0)] < p[("rule4_beats", 10, 2.0)]
    assert p[("rule5_equivalent", 10, 0.5)] < p[("rule5_equivalent", 10, 2.0)]
    assert p[("rule10_majority", 3, 0.9)] == 0.0  # 3 seeds cannot show a majority
    assert p[("rule10_majority", 10, 0.9)] == pytest.approx(
        sps.binom.sf(8, 10, 0.9))  # 9 or 10 of 10
    assert a["nominal"] == stats.ONE_SIDED and a["interval"] == "Student t"
