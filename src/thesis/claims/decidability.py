"""Which claims the rules can decide, and at how many seeds: a claim whose thesis-shaped
synthetic data (its finding at its published size) reaches "reproduced", and whose
reversed finding reaches "not reproduced", first at :data:`SEEDS_NEEDED` seeds on the
grid :data:`SEED_GRID` (``tests/claims/test_decidability.py`` checks each entry on the
chapters' test fixtures). A claim that needs more seeds than the paper profile runs for
the results it reads (:func:`thesis.claims.kinds.paper_seeds`), or that no seed count on
the grid decides, is *untestable at the paper profile*, with its reason
(:data:`UNTESTABLE`).

The entries cover the claims whose fixtures take a seed count (chapters 2 and 3, chapter
6's rate and existence claims, chapter 7's budget claims); the others are not sized
yet. Chapter 6's sentences about what the method usually does need 10 seeds (a majority
shown: 9 or 10 of 10), which the paper profile runs. The fixtures' per-seed noise is their own
(small), so a count of 3 says the rule does not stand in the way, not that 3 real seeds
suffice; :mod:`thesis.claims.kinds` sizes an inconclusive verdict at its measured spread.
"""

from __future__ import annotations

from collections.abc import Iterable

from thesis.claims import kinds

#: Seed counts the decidability test tries.
SEED_GRID = (3, 5, 10, 20, 40, 100)

#: Claim id -> the smallest seed count of :data:`SEED_GRID` at which the thesis-shaped
#: finding is reproduced and the reversed one not reproduced (None: none up to 100).
SEEDS_NEEDED: dict[str, int | None] = {
    "ch2.spatial_transformers_beat_plain": 100,
    "ch2.recurrent_beats_feedforward": None,
    "ch2.chirpz_similar_to_bilinear_no_skew": 3,
    "ch2.chirpz_reaches_1_8_percent": 3,
    "ch3.half_ellipse_beats_sine_at_high_speed": 3,
    "ch3.spline_fastest": 3,
    "ch3.half_ellipse_most_robust": 3,
    "ch3.scapulae_needed_for_fast_turning": 3,
    "ch3.scapulae_maintain_speed": 3,
    "ch3.turning_without_scapulae_possible": 3,
    "ch6.trot_h50_b5_stable": 3,
    "ch6.phase1_only_fails": 10,
    "ch6.learns_in_a_couple_of_strides": 10,
    "ch8.ch6_stable_trot_in_few_periods_without_memory": 10,
    "ch6.linear_feedback_insufficient": 10,
    "ch6.memoryless_feedback_trots": 3,
    "ch7.vision_control_learned_through_camera": 3,
    "ch8.ch7_pendulum_from_pixels": 3,
    "ch8.ch7_gait_in_500_evaluations": 3,
    "ch7.arm_fixed_point_learned_quickly": 10,
    "ch7.scales_to_millions_of_parameters": 10,
}

_FAILED_NETS = ("networks can sit at chance, so the comparison is rule 3b's: with no "
                "failure seen the failure rate may still be up to 77 % at 3 seeds and about "
                "10 % at 40, each failed seed's difference anywhere within +-90.6 points "
                "(a network at chance errs on 9 of 10 digits, within its binomial spread)")
_ONE_PENDULUM = ("existence without a replication of each seed needs 2 seeds that show it "
                 "(one is what runs passing by chance at 5 % give), so one seed cannot "
                 "decide it; the paper profile runs 1 pendulum seed")
#: Claim id -> why it cannot be decided at the paper profile's seed count.
UNTESTABLE: dict[str, str] = {
    "ch2.spatial_transformers_beat_plain": _FAILED_NETS + "; the thesis's 4.5-point "
    "advantage is decided from about 100 seeds (paper profile: 3)",
    "ch2.recurrent_beats_feedforward": _FAILED_NETS + "; the recurrent network's "
    "advantage of about 0.5 points is not decided at 100 seeds",
    "ch7.arm_fixed_point_learned_quickly": "'learned within N evaluations' is what the "
    "method does as a rule, a majority of seeds, which fewer than 6 seeds cannot show "
    "(2^-5 > 2.5 %); the thesis-shaped runs decide from 10 on the grid (paper profile: 3)",
    "ch7.vision_control_learned_through_camera": _ONE_PENDULUM,
    "ch8.ch7_pendulum_from_pixels": _ONE_PENDULUM,
    "ch7.scales_to_millions_of_parameters": "as ch7.arm_fixed_point_learned_quickly: a "
    "majority of seeds within the budget needs at least 6 seeds (paper profile: 1)",
}


def record(claim_id: str, requires: Iterable[str]) -> dict | None:
    """``{"seeds_needed", "paper_seeds", "untestable"}`` for a sized claim (None
    otherwise); ``untestable`` is the reason it cannot be decided at the paper profile
    ("" when it can)."""
    if claim_id not in SEEDS_NEEDED:
        return None
    need, paper = SEEDS_NEEDED[claim_id], kinds.paper_seeds(requires)
    return {"seeds_needed": need, "paper_seeds": paper,
            "untestable": UNTESTABLE.get(claim_id, "")}
