"""The five selections of §5.3.1 built so that no recording feeds both sides of a fold.

The thesis: "Then we select a total of 3000 samples for each terrain type and do this five
times. Three of these are used for threefold cross-validation while optimizing the
parameters, the other two are used for twofold cross-validation during the verification
of the parameters. Any remaining relevant trials are added to the test set during
verification. We split all trials into parts as a final step". A fold trains on some
selections and validates (tunes) or tests (verifies) on another, so a trial cut across
two selections puts the same recording on both sides of a fold, and the tuning rewards
memorising a recording (its per-trial constants) instead of recognising a terrain.

Three modes (``ch5.protocol.selection``, the choice and its reasons in departure
``ch5.trial_disjoint_folds``):

* ``"trials"`` (primary): per terrain the trials are shuffled (seeded) and dealt *whole*
  to the selections in turn; a selection takes its ``samples`` time steps from the start
  of its trials, the unused rest of its last trial is dropped, and the next selection
  starts with the next trial. A selection thus holds one or two recordings per terrain,
  as in the previous protocol, but never shares one with another selection.
* ``"parts"`` (sensitivity variant, "parts across trials"): every trial is cut into the
  parts of :func:`thesis.ch5.protocol.split_lengths`; the shuffled trials are dealt
  round-robin to the selections (each trial to one selection only), each dealt trial
  gives one randomly chosen part, and a selection that is still short takes further
  parts of its own trials. A selection then spans as many recordings, and so as many
  (gait, frequency) cells, as the terrain's trials allow, and folds stay trial-disjoint
  because whole trials are assigned to sides and parts are drawn within each side.
* ``"blocks"`` (consecutive blocks, :func:`thesis.ch5.protocol.make_selections`):
  consecutive blocks of the concatenated trials; a trial may be cut across selections.

Where a terrain has too few trials for five disjoint selections, ``"trials"`` and
``"parts"`` fall back per terrain, in this order (recorded as :attr:`Selections.level`):

1. ``"disjoint"``: all five selections trial-disjoint;
2. ``"stages"``: the three tuning selections are trial-disjoint among themselves and the
   two verification selections among themselves, but verification reuses recordings of
   the tuning (unused trials first; samples from the trials' ends in ``"trials"``, parts
   the tuning did not take in ``"parts"``). No fold has a recording on both sides; the
   tuned hyper-parameters have seen recordings the verification tests on;
3. ``"cut"``: the ``"blocks"`` protocol's blocks for that terrain (a fold's sides share its
   recordings; the default profile's terrains never get here, the smoke profile's
   one-trial terrains do).

Trials no selection touched are the "remaining relevant trials" (test set); the untouched
rest of a touched trial is dropped.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from thesis.ch5 import protocol as P

__all__ = ["MODES", "LEVELS", "TUNING", "VERIFICATION", "Selections", "select",
           "shared_share"]

MODES = ("trials", "parts", "blocks")
LEVELS = ("disjoint", "stages", "cut", "blocks")
#: Selection indices of the threefold tuning and the twofold verification (§5.3.1).
TUNING, VERIFICATION = (0, 1, 2), (3, 4)


@dataclass(frozen=True)
class Selections:
    """One seed's selections.

    Attributes:
        selections: ``selections[k]`` the segments of selection k (every terrain).
        remaining: trials no selection touched (sorted).
        level: terrain index -> how its selections were built (:data:`LEVELS`).
    """

    selections: list
    remaining: list
    level: dict = field(default_factory=dict)


def _fill_trials(order, lengths, n_groups: int, samples: int, from_end: bool):
    """Deal whole trials of ``order`` to ``n_groups`` groups of ``samples`` time steps.
    Returns (groups of segments, trials used) or None when the trials run out."""
    groups: list[list[P.Segment]] = [[] for _ in range(n_groups)]
    used: list[int] = []
    g, have = 0, 0
    for tr in order:
        if g == n_groups:
            break
        L = int(lengths[tr])
        if L <= 0:
            continue
        take = min(L, samples - have)
        groups[g].append(P.Segment(int(tr), L - take, L) if from_end else
                         P.Segment(int(tr), 0, take))
        used.append(int(tr))
        have += take
        if have == samples:
            g, have = g + 1, 0
    return (groups, used) if g == n_groups else None


def _part_bounds(length: int, part_target: int) -> list[tuple[int, int]]:
    edges = np.concatenate([[0], np.cumsum(P.split_lengths(length, part_target))])
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:])]


def _fill_parts(order, n_groups: int, samples: int, avail: dict):
    """Deal trials of ``order`` round-robin to ``n_groups`` groups, one part each, then
    top short groups up with further parts of their own trials. ``avail`` (trial -> part
    bounds not yet taken, in random order) is consumed. Returns (groups, trials used) or
    None when a group cannot be filled."""
    groups: list[list[P.Segment]] = [[] for _ in range(n_groups)]
    members: list[list[int]] = [[] for _ in range(n_groups)]
    need = [samples] * n_groups
    used: list[int] = []

    def take(g: int, tr: int) -> None:
        a, b = avail[tr].pop()
        n = min(b - a, need[g])
        groups[g].append(P.Segment(int(tr), a, a + n))
        need[g] -= n

    p = 0
    for tr in order:
        needy = [g for g in range(n_groups) if need[g] > 0]
        if not needy:
            break
        if not avail.get(tr):
            continue
        g = next(i % n_groups for i in range(p, p + n_groups) if need[i % n_groups] > 0)
        members[g].append(int(tr))
        used.append(int(tr))
        take(g, int(tr))
        p = g + 1
    for g in range(n_groups):
        while need[g] > 0:
            have = [tr for tr in members[g] if avail[tr]]
            if not have:
                return None
            for tr in have:
                if need[g] <= 0:
                    break
                take(g, tr)
    for g in groups:
        g.sort(key=lambda s: (s.trial, s.start))
    return groups, used


def _one_terrain(mode, mine, lengths, rng, samples, part_target):
    """Selections of one terrain's (shuffled) trials ``mine``: (groups, level) or None."""
    n = len(TUNING) + len(VERIFICATION)
    if mode == "trials":
        full = _fill_trials(mine, lengths, n, samples, from_end=False)
        if full is not None:
            return full[0], "disjoint"
        tune = _fill_trials(mine, lengths, len(TUNING), samples, from_end=False)
        if tune is not None:
            rest = [t for t in mine if t not in set(tune[1])] + list(tune[1])
            ver = _fill_trials(rest, lengths, len(VERIFICATION), samples, from_end=True)
            if ver is not None:
                return tune[0] + ver[0], "stages"
        return None
    avail = {}
    for t in mine:
        bounds = _part_bounds(int(lengths[t]), part_target) if int(lengths[t]) > 0 else []
        avail[t] = [bounds[i] for i in rng.permutation(len(bounds))]
    trial_avail = {t: list(v) for t, v in avail.items()}
    full = _fill_parts(mine, n, samples, trial_avail)
    if full is not None:
        return full[0], "disjoint"
    trial_avail = {t: list(v) for t, v in avail.items()}
    tune = _fill_parts(mine, len(TUNING), samples, trial_avail)
    if tune is not None:
        rest = [t for t in mine if t not in set(tune[1])] + list(tune[1])
        # parts the tuning did not take first (popped from the end), then its own
        reuse = {t: [b for b in avail[t] if b not in trial_avail[t]] + trial_avail[t]
                 for t in avail}
        ver = _fill_parts(rest, len(VERIFICATION), samples, reuse)
        if ver is not None:
            return tune[0] + ver[0], "stages"
    return None


def select(mode: str, lengths: np.ndarray, terrain: np.ndarray, trials: np.ndarray,
           rng: np.random.Generator, n_selections: int, samples: int, part_target: int,
           terrain_names=None) -> Selections:
    """The selections of §5.3.1 in ``mode`` (see module docstring).

    Args:
        mode: one of :data:`MODES`.
        lengths, terrain: (n_trials,) per trial of the recordings [samples; index].
        trials: indices of the trials the experiment uses.
        rng: the seed's generator (shuffles and part choices).
        n_selections: must be 5 (three tuning + two verification selections).
        samples: time steps per terrain in each selection.
        part_target: target part length [samples] (``"parts"`` mode).
    Raises:
        ValueError: unknown mode, ``n_selections`` not 5, or a terrain with fewer than
            ``n_selections * samples`` samples.
    """
    if mode not in MODES:
        raise ValueError(f"unknown selection mode {mode!r}; one of {MODES}")
    if int(n_selections) != len(TUNING) + len(VERIFICATION):
        raise ValueError(f"{n_selections} selections: the protocol needs "
                         f"{len(TUNING)} tuning + {len(VERIFICATION)} verification")
    trials = np.asarray(trials, int)
    if mode == "blocks":
        sels, rest = P.make_selections(lengths, terrain, trials, rng, n_selections, samples,
                                       terrain_names)
        return Selections(sels, rest, {int(r): "blocks" for r in np.unique(terrain[trials])})
    selections: list[list[P.Segment]] = [[] for _ in range(n_selections)]
    remaining: list[int] = []
    level: dict[int, str] = {}
    need = n_selections * samples
    for r in np.unique(terrain[trials]):
        mine = trials[terrain[trials] == r]
        mine = [int(t) for t in mine[rng.permutation(len(mine))]]
        total = int(lengths[mine].sum())
        if total < need:
            name = terrain_names[r] if terrain_names is not None else r
            raise ValueError(f"terrain {name}: {total} samples in {len(mine)} trials, "
                             f"{n_selections} selections of {samples} need {need}")
        got = _one_terrain(mode, mine, lengths, rng, int(samples), int(part_target))
        if got is None:  # too few trials: the previous protocol's blocks for this terrain
            sels, _ = P.make_selections(lengths, terrain, np.array(mine), rng, n_selections,
                                        samples, terrain_names)
            groups, lev = sels, "cut"
        else:
            groups, lev = got
        for k in range(n_selections):
            selections[k].extend(groups[k])
        touched = {s.trial for g in groups for s in g}
        remaining += [t for t in mine if t not in touched]
        level[int(r)] = lev
    return Selections(selections, sorted(remaining), level)


def shared_share(split: P.Split) -> float:
    """Percent of the time steps on the evaluation side of ``split`` that come from a
    trial (recording) that also feeds its training side; 0 for a trial-disjoint fold,
    NaN for an empty evaluation side."""
    train = {s.trial for s in split.train}
    total = sum(s.length for s in split.test)
    shared = sum(s.length for s in split.test if s.trial in train)
    return 100.0 * shared / total if total else float("nan")
