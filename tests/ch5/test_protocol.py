"""Selections, folds, parts and scores of §5.3.1-5.3.2."""

import numpy as np
import pytest

from thesis.ch5 import protocol as P


def test_parts_follow_the_thesis_lengths():
    for L in range(281, 5000, 37):
        parts = P.split_lengths(L, 375)
        assert parts.sum() == L
        assert parts.min() >= 281 and parts.max() < 563, (L, parts)


def _trials():
    lengths = np.array([3000, 4000, 3500, 6000, 5000, 5200, 3100, 3300, 3900, 4100])
    terrain = np.array([0, 0, 0, 0, 1, 1, 1, 1, 1, 1])
    return lengths, terrain


def test_selections_are_disjoint_blocks_and_remaining_trials_untouched():
    lengths, terrain = _trials()
    sels, rest = P.make_selections(lengths, terrain, np.arange(10), np.random.default_rng(0),
                                   5, 3000)
    assert len(sels) == 5
    used = {}
    for k, sel in enumerate(sels):
        for r in (0, 1):
            assert sum(s.length for s in sel if terrain[s.trial] == r) == 3000
        for s in sel:
            for t in range(s.start, s.stop):
                assert (s.trial, t) not in used
                used[(s.trial, t)] = k
    touched = {s.trial for sel in sels for s in sel}
    assert set(rest) == set(range(10)) - touched
    assert rest  # terrain 1 has more than 15000 samples


def test_selection_fails_clearly_without_enough_samples():
    lengths, terrain = _trials()
    with pytest.raises(ValueError, match="terrain C"):
        P.make_selections(lengths, terrain, np.arange(4), np.random.default_rng(0), 5, 4000,
                          terrain_names=("C", "R"))


def test_folds():
    sels = [[P.Segment(k, 0, 10)] for k in range(5)]
    tune = P.tuning_folds(sels)
    assert [len(f.train) for f in tune] == [2, 2, 2]
    assert [f.test[0].trial for f in tune] == [0, 1, 2]
    ver = P.verification_folds(sels, [7], np.full(8, 10))
    assert ver[0].train[0].trial == 3 and [s.trial for s in ver[0].test] == [4, 7]
    assert ver[1].train[0].trial == 4 and [s.trial for s in ver[1].test] == [3, 7]


def test_parts_labels_and_scores():
    signals = np.arange(40, dtype=float)[:, None] * np.ones((1, 3))
    parts = P.to_parts(signals, np.array([0, 20]), np.array([2, 4]),
                       [P.Segment(0, 0, 20), P.Segment(1, 5, 15)], [0, 2], 7)
    assert list(parts.length) == [7, 7, 6, 10]
    assert list(parts.label) == [2, 2, 2, 4]
    np.testing.assert_array_equal(P.flat(parts.x, parts.length)[:, 0],
                                  np.r_[np.arange(20), np.arange(25, 35)])
    labels = parts.labels()
    assert P.accuracy(labels, labels) == 100.0
    pred = labels.copy()
    pred[:10] = 0
    assert P.accuracy(pred, labels) == pytest.approx(100 * 20 / 30)
    c = P.confusion(pred, labels, 5)
    assert c[2, 0] == 10 and c.sum() == 30


def test_normalise():
    x = np.random.default_rng(0).normal(3, 2, (500, 4))
    x[:, 3] = 1.0
    z, mean, std = P.normalise(x)
    np.testing.assert_allclose(z[:, :3].mean(0), 0, atol=1e-12)
    np.testing.assert_allclose(z[:, :3].std(0), 1, atol=1e-12)
    assert np.all(z[:, 3] == 0)
