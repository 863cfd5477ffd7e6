"""A decidability test per sized claim (:mod:`thesis.claims.decidability`): thesis-shaped
synthetic data reach "reproduced", the reversed finding "not reproduced", first at the
recorded seed count; a claim that needs more seeds than the paper profile runs (or none
on the grid) is declared untestable there with its reason."""

from __future__ import annotations

import pytest

from thesis import claims
from thesis.claims import decidability as D
from thesis.claims import kinds

from .decidable_cases import CASES


def _decided(cid: str, n: int) -> tuple[str, str]:
    support, reverse = CASES[cid]
    c = claims.get(cid)
    return c.check(support(n)).status, c.check(reverse(n)).status


def test_every_sized_claim_has_thesis_shaped_cases():
    assert set(CASES) == set(D.SEEDS_NEEDED)


def test_every_claim_is_sized_or_declared_untestable():
    """Each claim has its seed count; one that no grid point decides has its reason."""
    assert set(D.SEEDS_NEEDED) == {c.id for c in claims.CLAIMS}
    assert all(cid in D.UNTESTABLE for cid, need in D.SEEDS_NEEDED.items() if need is None)
    assert set(D.UNTESTABLE) <= set(D.SEEDS_NEEDED)


@pytest.mark.parametrize("cid", sorted(D.SEEDS_NEEDED))
def test_the_recorded_seed_count_is_the_first_that_decides(cid):
    need = D.SEEDS_NEEDED[cid]
    below = [n for n in D.SEED_GRID if need is None or n < need]
    for n in below[-1:]:  # the grid point just below decides nothing both ways
        assert _decided(cid, n) != ("reproduced", "not_reproduced"), (cid, n)
    if need is not None:
        assert _decided(cid, need) == ("reproduced", "not_reproduced"), cid


@pytest.mark.parametrize("cid", sorted(D.SEEDS_NEEDED))
def test_a_claim_beyond_the_paper_profile_is_declared_untestable_with_its_reason(cid):
    rec = D.record(cid, claims.get(cid).requires)
    need, paper = rec["seeds_needed"], rec["paper_seeds"]
    beyond = need is None or (paper is not None and need > paper)
    assert bool(rec["untestable"]) == beyond, (cid, need, paper)


def test_the_record_is_in_the_claims_entry():
    v = claims.evaluate(claims.get("ch7.arm_fixed_point_learned_quickly"), {})
    assert v["decidability"]["seeds_needed"] == 10 and v["decidability"]["paper_seeds"] == 3
    assert "majority" in v["decidability"]["untestable"]
    assert kinds.paper_seeds(["ch7/arm_random"]) == 1


def test_a_claim_no_seed_count_decides_carries_its_reason_in_its_entry():
    v = claims.evaluate(claims.get("ch4.speedup_from_reduced_search_space"), {})
    assert v["decidability"]["seeds_needed"] is None and v["decidability"]["paper_seeds"] == 10
    assert "intervention" in v["decidability"]["untestable"]
