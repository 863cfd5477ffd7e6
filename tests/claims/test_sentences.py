"""thesis.claims.sentences: the log-ratio likeness, the chance gate and the majority rule's
seed count, on numbers whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.claims import sentences, stats


def test_log_margin_is_the_smaller_side_of_the_relative_band():
    assert sentences.log_margin(0.25) == pytest.approx(np.log(1.25))
    assert sentences.log_margin(0.25) < -np.log(0.75)
    with pytest.raises(ValueError):
        sentences.log_margin(1.5)
    # a 36 % gain with 25 % of it allowed: ratios 1.27 to 1.45, the smaller log side
    m = sentences.gain_log_margin(0.36)
    assert m == pytest.approx(min(np.log(1.45 / 1.36), np.log(1.36 / 1.27)))
    with pytest.raises(ValueError):
        sentences.gain_log_margin(-0.1)


def test_ratio_likeness_on_the_log_scale():
    rng = np.random.default_rng(0)
    den = rng.uniform(1.0, 2.0, 6)
    like = sentences.decide_ratio_like(den * 1.02, den, label="r")
    assert like.status == "reproduced"
    assert like.measured["r_geometric_mean"] == pytest.approx(1.02)
    far = sentences.decide_ratio_like(den * 1.5, den, label="r")
    assert far.status == "not_reproduced"
    at_target = sentences.decide_ratio_like(den * 1.7, den, target=1.7, label="r")
    assert at_target.status == "reproduced"
    # non-positive values have no ratio: dropped and counted
    bad = sentences.decide_ratio_like(np.r_[den[:3] * 1.02, -1.0], np.r_[den[:3], 1.0])
    assert bad.measured["n_seeds_without_ratio"] == 1 and bad.measured["n_seeds"] == 3
    with pytest.raises(ValueError):
        sentences.decide_ratio_like([1.0, 2.0], [1.0], label="r")
    with pytest.raises(ValueError):
        sentences.decide_ratio_like([1.0], [1.0], target=0.0)


def test_better_than_chance_is_an_exact_binomial_test():
    out = sentences.better_than_chance([0.9, 0.8, 0.02, np.nan], 100)
    assert out.tolist() == [False, True, True, False]
    # 85 errors in 100 against 90: P(X <= 85) = 0.073, not below 2.5 %
    assert not sentences.better_than_chance([0.85], 100)[0]
    with pytest.raises(ValueError):
        sentences.better_than_chance([0.1], 0)


def test_majority_needs_six_seeds_and_says_so():
    assert sentences.min_seeds_for_majority() == 6
    assert 2.0 ** -6 <= stats.ONE_SIDED < 2.0 ** -5
    five = sentences.decide_majority_or_untestable([1, 1, 1, 1, 1], label="x")
    assert five.status == "inconclusive" and "not testable" in five.detail
    assert five.measured["seeds_needed"] == 6
    assert sentences.decide_majority_or_untestable([1] * 6, label="x").status == "reproduced"
    assert sentences.decide_majority_or_untestable([0] * 6, label="x").status == (
        "not_reproduced")
