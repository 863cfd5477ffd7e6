"""Every inconclusive verdict says why, as one of a few kinds (:mod:`thesis.claims.kinds`),
and the report's status counts each kind per chapter."""

from __future__ import annotations

import numpy as np
import pytest

from thesis import claims
from thesis.claims import kinds, stats

from . import test_ch7 as c7


def _entry(v, requires=("ch3/fig3_4",), **extra) -> dict:
    return {"status": v.status, "measured": v.measured, "detail": v.detail,
            "requires": list(requires), **extra}


def test_a_mean_needs_the_seeds_of_a_powered_t_test():
    """An advantage of 0.87 sd: the one-sided t test at 2.5 % with 80 % power needs 13
    seeds (simulated: 81 % of 2000 draws of 13 seeds reproduce it); half the effect
    about four times as many."""
    x = np.array([-0.2, 0.5, 1.6, 0.9, 0.2])  # mean 0.6, sd 0.69
    v = stats.decide_beats(x, np.zeros(5), higher_is_better=True)
    assert v.status == "inconclusive"
    n1 = kinds.seeds_needed(v.measured)
    v2 = stats.decide_beats(x - 0.3, np.zeros(5), higher_is_better=True)
    assert n1 == 13 and 3 * n1 < kinds.seeds_needed(v2.measured) < 4.5 * n1
    # the sentence-level kind: ch3 runs 5 seeds in the paper profile
    got = kinds.classify(_entry(v))
    assert got["kind"] == "ambiguous at any seed count the paper profile has"
    assert got["seeds_needed"] == n1 and got["paper_seeds"] == 5
    # 0.1 more: 10 seeds, which chapter 4's paper profile runs
    v3 = stats.decide_beats(x + 0.1, np.zeros(5), higher_is_better=True)
    got = kinds.classify(_entry(v3, requires=("ch4/fig4_7",)))
    assert v3.status == "inconclusive"
    assert got == {"kind": "needs about 10 seeds", "why": "power 80 % at the measured effect",
                   "seeds_needed": 10, "paper_seeds": 10}


def test_counts_are_sized_by_their_exact_test():
    """8 of 10 seeds: the majority test (rule 10) reaches 80 % power at a rate of 0.8 at
    about 20 seeds; an existence whose twin repeats nothing has nothing to size."""
    v = stats.decide_majority([1, 1, 1, 1, 0, 1, 1, 1, 0, 1])
    assert v.status == "inconclusive" and kinds.seeds_needed(v.measured) == 20
    lone = stats.decide_exists([1, 0, 0], replicated=[0, 0, 0])
    assert kinds.seeds_needed(lone.measured) == np.inf
    assert kinds.classify(_entry(lone))["kind"] == (
        "ambiguous at any seed count the paper profile has")


def test_model_validation_and_profile_scale_are_their_own_kinds():
    v = stats.decide_beats([0.1, -0.1, 0.2], [0.0] * 3, higher_is_better=True)
    failed = _entry(v, model_validation={"unvalidated": True,
                                         "failed_targets": [{"target": "duty_factor"}]})
    assert kinds.classify(failed) == {"kind": "model failed validation",
                                      "why": "failed targets: duty_factor",
                                      "seeds_needed": None, "paper_seeds": 5}
    small = stats.untestable(["a batch of 8, the thesis's 128"])
    assert kinds.classify(_entry(small))["kind"] == "not testable at this profile's scale"
    ok = stats.decide_beats([1.0, 1.1, 0.9], [0.0] * 3, higher_is_better=True)
    assert kinds.classify(_entry(ok)) is None


def test_every_inconclusive_verdict_of_evaluate_carries_its_kind():
    three = c7.curve("evaluation", 300, final=0.002, start=0.5, **c7.ARM1_THESIS)
    v = claims.evaluate(claims.get("ch7.arm_fixed_point_learned_quickly"),
                        {"ch7/arm_fixed": three})
    assert v["status"] == "inconclusive"
    # 3 of 3 seeds in time: a majority at 80 % power needs about 6, the paper profile runs 3
    assert v["inconclusive_kind"]["kind"] == "ambiguous at any seed count the paper profile has"
    assert v["inconclusive_kind"]["seeds_needed"] == 6
    six = c7.curve("evaluation", 300, final=0.002, start=0.5, seeds=6, **c7.ARM1_THESIS)
    v = claims.evaluate(claims.get("ch7.arm_fixed_point_learned_quickly"),
                        {"ch7/arm_fixed": six})
    assert v["status"] == "reproduced" and "inconclusive_kind" not in v


@pytest.mark.parametrize("kind", ["needs about 12 seeds", "model failed validation"])
def test_the_status_table_counts_each_kind_per_chapter(kind):
    from thesis.report import status

    entries = [{"id": "ch3.a", "chapter": 3, "status": "inconclusive",
                "inconclusive_kind": {"kind": kind}},
               {"id": "ch3.b", "chapter": 3, "status": "inconclusive",
                "inconclusive_kind": {"kind": "ambiguous at any seed count the paper "
                                              "profile has"}},
               {"id": "ch3.c", "chapter": 3, "status": "reproduced"}]
    rows = {r.chapter: r for r in status.chapter_status({}, entries)}
    counted = "needs more seeds" if kind.startswith("needs") else kind
    assert rows["ch3"].kinds == {counted: 1,
                                 "ambiguous at any seed count the paper profile has": 1}
    md = "\n".join(status.status_md(list(rows.values())))
    assert f"(inconclusive: 1 {counted}, 1 ambiguous" in md
    assert f"inconclusive: 1 {counted}" in status.status_html(list(rows.values()))


def test_the_paper_seed_count_is_a_seeds_list_not_any_list_a_result_reads():
    """ch4's slope results read ``ch4.conditions.grades`` (two grades, not two seeds) and
    coopt's gradients read ``coopt.hidden`` (two widths): the seed counts are the
    sections' ``seeds`` (10 for chapter 4, 5 for coopt's gradients)."""
    assert kinds.paper_seeds(["ch4/fig4_5"]) == 10
    assert kinds.paper_seeds(["ch4/table4_2"]) == 10
    assert kinds.paper_seeds(["coopt/gradients"]) == 5
    assert kinds.paper_seeds(["ch7/arm_random"]) == 1
