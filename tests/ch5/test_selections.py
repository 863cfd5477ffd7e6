"""Selections of §5.3.1 whose folds cannot memorise a recording."""

import numpy as np
import pytest

from thesis.ch5 import protocol as P
from thesis.ch5 import selections as SEL

#: Trials per terrain as in Tab. 5.1 (F 49, S 45, L 16, C 3, R 5).
_COUNTS = (49, 45, 16, 3, 5)


def _table(seed=0, counts=_COUNTS):
    """(lengths, terrain) of a trial table like the default profile's recordings:
    3000-6500 samples, cardboard 5000-6500, a few trials stopped early (turned over)."""
    rng = np.random.default_rng(seed)
    terrain = np.repeat(np.arange(len(counts)), counts)
    lengths = rng.integers(3000, 6501, terrain.size)
    lengths[terrain == 3] = rng.integers(5000, 6501, int((terrain == 3).sum()))
    stopped = rng.choice(np.flatnonzero(terrain < 2), 6, replace=False)
    lengths[stopped] = rng.integers(400, 2500, stopped.size)
    return lengths, terrain


def _select(mode, seed=0, samples=3000, counts=_COUNTS):
    lengths, terrain = _table(seed, counts)
    sel = SEL.select(mode, lengths, terrain, np.arange(terrain.size),
                     np.random.default_rng(seed), 5, samples, 375, ("F", "S", "L", "C", "R"))
    return sel, lengths, terrain


def assert_trial_disjoint(sel, lengths):
    """No recording feeds both sides of a tuning or verification fold."""
    folds = (P.tuning_folds(sel.selections)
             + P.verification_folds(sel.selections, sel.remaining, lengths))
    for i, fold in enumerate(folds):
        assert SEL.shared_share(fold) == 0.0, (i, SEL.shared_share(fold))


@pytest.mark.parametrize("mode", ["trials", "parts"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_folds_are_trial_disjoint(mode, seed):
    sel, lengths, _ = _select(mode, seed)
    assert_trial_disjoint(sel, lengths)


def test_the_previous_block_selections_are_not():
    """The check above fails on the previous protocol: its consecutive blocks cut a
    recording across selections, so folds share recordings between their sides."""
    sel, lengths, _ = _select("blocks")
    with pytest.raises(AssertionError):
        assert_trial_disjoint(sel, lengths)
    tune = P.tuning_folds(sel.selections)
    assert max(SEL.shared_share(f) for f in tune) > 50.0


@pytest.mark.parametrize("mode", ["trials", "parts", "blocks"])
def test_every_selection_has_its_samples_per_terrain(mode):
    sel, lengths, terrain = _select(mode)
    owner = {}
    for k, segs in enumerate(sel.selections):
        for r in range(5):
            assert sum(s.length for s in segs if terrain[s.trial] == r) == 3000, (k, r)
        for s in segs:
            assert 0 <= s.start < s.stop <= lengths[s.trial]
            if mode != "blocks" and sel.level[int(terrain[s.trial])] == "disjoint":
                assert owner.setdefault(s.trial, k) == k, (s.trial, k)  # one selection
    touched = {s.trial for segs in sel.selections for s in segs}
    assert set(sel.remaining) == set(range(terrain.size)) - touched


@pytest.mark.parametrize("mode", ["trials", "parts"])
def test_levels_fall_back_with_few_trials(mode):
    sel, lengths, terrain = _select(mode)
    assert sel.level == {0: "disjoint", 1: "disjoint", 2: "disjoint", 3: "stages",
                         4: "disjoint"}
    # cardboard's three trials: the tuning selections disjoint among themselves, the
    # verification reuses them
    c_tune = [{s.trial for s in sel.selections[k] if terrain[s.trial] == 3} for k in (0, 1, 2)]
    assert all(len(a & b) == 0 for i, a in enumerate(c_tune) for b in c_tune[i + 1:])
    one, _, _ = _select(mode, samples=500, counts=(8, 8, 1))
    assert one.level[2] == "cut"  # one trial cannot be split into disjoint selections


def test_parts_span_more_recordings_than_whole_trials():
    trials, _, terrain = _select("trials")
    parts, _, _ = _select("parts")
    per = lambda sel: np.mean([len({s.trial for s in segs if terrain[s.trial] == 0})  # noqa
                               for segs in sel.selections])
    assert per(trials) <= 2.0
    assert per(parts) >= 6.0
    for segs in parts.selections:
        assert max(s.length for s in segs) <= 563


def test_bad_mode_and_selection_count_are_refused():
    lengths, terrain = _table()
    with pytest.raises(ValueError, match="unknown selection mode"):
        SEL.select("random", lengths, terrain, np.arange(terrain.size),
                   np.random.default_rng(0), 5, 3000, 375)
    with pytest.raises(ValueError, match="5 selections|tuning"):
        SEL.select("trials", lengths, terrain, np.arange(terrain.size),
                   np.random.default_rng(0), 4, 3000, 375)
    with pytest.raises(ValueError, match="terrain C"):
        SEL.select("trials", lengths, terrain, np.arange(terrain.size),
                   np.random.default_rng(0), 5, 9000, 375, ("F", "S", "L", "C", "R"))


def test_shared_share_counts_time_steps():
    split = P.Split(train=(P.Segment(0, 0, 10),),
                    test=(P.Segment(0, 10, 40), P.Segment(1, 0, 10)))
    assert SEL.shared_share(split) == pytest.approx(75.0)
    assert np.isnan(SEL.shared_share(P.Split(train=(), test=())))
